% nlvib_ex07.m: NLvib's example 7 (a chain of three oscillators with two Jenkins elements, two cubic
% springs and a unilateral spring) run by NLvib itself, its points written to CSV for frictiondamp's
% comparison (examples/nlvib_ex07.py, docs/contacts_normal.md).
%
% This script is frictiondamp's own; NLvib is not part of frictiondamp and is not copied here.
% To run it:
%   1. get NLvib 1.3 (GPL-3.0): git clone https://github.com/maltekrack/NLvib  (or the release
%      archive); the script needs SRC/HB_residual.m, SRC/solve_and_continue.m and
%      SRC/MechanicalSystems/{MechanicalSystem,ChainOfOscillators}.m;
%   2. set NLVIB to that directory (default /work/peers/NLvib);
%   3. from the repository root:  octave --no-gui --eval "run('benchmarks/peers/nlvib_ex07.m')"
%      (or matlab -batch "run('benchmarks/peers/nlvib_ex07.m')"); OUT sets the CSV path
%      (default docs/data/nlvib_ex07.csv).
% The system, H = 7, N = 1024, Om from 0.5 to 2 and the step ds = 0.005 are those of NLvib's
% EXAMPLES/07_multiDOFoscillator_multipleNonlinearities/multiDOFoscillator_multipleNonlinearities.m;
% the continuation runs with NLvib's defaults (solve_and_continue; fsolve with NLvib's options,
% passed explicitly for Octave).
%
% Optional settings (environment variables), used to cover NLvib's branch in pieces:
%   OM_S, OM_E  start and end of the continuation (default 0.5 and 2);
%   START       a CSV written by this script: the continuation starts from its row whose Om is
%               nearest OM_S (NLvib first re-solves there at fixed Om) instead of the linear
%               guess at 0.5;
%   NLVIB_DIAG_LOG, NLVIB_DIAG_DIR  NLVIB_DIAG_DIR is added to the path; with
%               NLVIB_DIAG_DIR=benchmarks/peers and a call to benchmarks/peers/nlvib_diag_hook.m
%               added to NLvib's solve_and_continue.m (that file says where), every corrector
%               solve, accepted or not, is logged to NLVIB_DIAG_LOG; the points themselves do
%               not depend on it.
%
% CSV columns: Om, the RMS measure NLvib's example plots for q1, q2, q3
% (sqrt(sum of the squared coefficients)/sqrt(2)), then the coefficients of q1, q2, q3 in
% frictiondamp's layout [X0, Xc1, Xs1, ..., Xc7, Xs7] per DOF (x = X0 + sum Xc_h cos(h tau) +
% Xs_h sin(h tau), the layout NLvib uses too), and last res_nlvib: the norm of NLvib's own
% harmonic-balance residual (HB_residual) at the accepted point, to tell converged points from
% points NLvib's fsolve gave up on.
nlvib = getenv('NLVIB');
if isempty(nlvib), nlvib = '/work/peers/NLvib'; end
out = getenv('OUT');
if isempty(out), out = 'docs/data/nlvib_ex07.csv'; end
addpath(fullfile(nlvib, 'SRC'));
addpath(fullfile(nlvib, 'SRC', 'MechanicalSystems'));

% (defined before its use: Octave reads a script's functions as it runs it)
function s = append_point(Y, out, n, L, resfun)
  % one row: Om, NLvib's RMS measure per DOF, the coefficients per DOF (layout above), and the
  % norm of NLvib's residual at the point
  C = reshape(Y(1:end-1), n, L);          % row d: DOF d's coefficients [X0, Xc1, Xs1, ...]
  r = norm(resfun(Y));
  dlmwrite(out, [Y(end), sqrt(sum(C.^2, 2))'/sqrt(2), reshape(C', 1, []), r], '-append', 'precision', '%.17g');
  s = struct();
end

% ---- the system of NLvib's example 7
mi = [1 1 1]; ki = [1 1 1 1]; di = .02*ki; Fex1 = [0;1;0];
knl = 20; muN = 1;
W1 = [1;0;0]; W2 = [-1;1;0];
nl{1} = struct('type','elasticDryFriction','stiffness',knl,'friction_limit_force',muN, ...
               'ishysteretic',true,'force_direction',W1);
nl{2} = struct('type','elasticDryFriction','stiffness',knl,'friction_limit_force',muN, ...
               'ishysteretic',true,'force_direction',W2);
nl{3} = struct('type','cubicSpring','stiffness',1.,'force_direction',[0;1;0]);
nl{4} = struct('type','cubicSpring','stiffness',1.,'force_direction',[0;-1;1]);
nl{5} = struct('type','unilateralSpring','stiffness',1.,'gap',.25,'force_direction',[0;0;1]);
dKfric = knl*(W1*W1' + W2*W2');
sys = ChainOfOscillators(mi, di, ki, nl, Fex1);

% ---- the frequency response, as in the example; each accepted point is appended to the CSV as
% it comes (NLvib's post-processing hook), so a long run can be read while it goes
H = 7; N = 2^10; Om_s = .5; Om_e = 2; ds = .005;
if ~isempty(getenv('OM_S')), Om_s = str2double(getenv('OM_S')); end
if ~isempty(getenv('OM_E')), Om_e = str2double(getenv('OM_E')); end
n = sys.n; L = 2*H + 1;
start = getenv('START');
if isempty(start)
  Q1 = (-Om_s^2*sys.M + 1i*Om_s*sys.D + sys.K + dKfric)\Fex1;
  x0 = zeros((2*H+1)*length(Q1), 1);
  x0(length(Q1)+(1:2*length(Q1))) = [real(Q1); -imag(Q1)];
else
  P = dlmread(start, ',', 2, 0);          % rows after the comment and the header
  [~, i] = min(abs(P(:, 1) - Om_s));
  x0 = reshape(reshape(P(i, 4 + (1:n*L)), L, n)', [], 1);
  Om_s = P(i, 1);
  printf('starting from %s, row at Om = %.17g\n', start, Om_s);
end
diag_dir = getenv('NLVIB_DIAG_DIR');
if ~isempty(diag_dir), addpath(diag_dir); end
names = {'Om', 'q1_rms', 'q2_rms', 'q3_rms'};
coef = {'X0'};
for h = 1:H, coef = [coef, {sprintf('Xc%d', h), sprintf('Xs%d', h)}]; end
for d = 1:n, for j = 1:L, names{end+1} = sprintf('q%d_%s', d, coef{j}); end, end
names{end+1} = 'res_nlvib';
fid = fopen(out, 'w');
fprintf(fid, '# NLvib 1.3 example 7 (H = 7, N = 1024), run by benchmarks/peers/nlvib_ex07.m in Octave %s; Om from %.17g to %g; start %s\n', version(), Om_s, Om_e, start);
fprintf(fid, '%s\n', strjoin(names, ','));
fclose(fid);
% NLvib's default solver options are optimset(optimset(@fsolve), ...), which Octave's optimset
% refuses (it takes a name, not a handle): the same options are passed explicitly instead.
Solopt = optimset(optimset('fsolve'), 'Display', 'off', 'Jacobian', 'on', 'MaxIter', 50);
resfun = @(Y) HB_residual(Y, sys, H, N, 'FRF');
[X, Solinfo] = solve_and_continue(x0, resfun, Om_s, Om_e, ds, struct(), ...
                                  @(Y) append_point(Y, out, n, L, resfun), Solopt);
printf('%d points written to %s; fsolve exit flags per point: %s\n', size(X, 2), out, ...
       mat2str(Solinfo.IEx'));
