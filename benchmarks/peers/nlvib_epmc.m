% NLvib 1.3's EPMC (nonlinear modal analysis, 'NMA' in HB_residual) on two friction chains, at
% fixed modal amplitudes, for the comparison with hbm.nonlinear_modes (tests/test_modes.py).
%
% Get NLvib 1.3 (GPL, not part of this repository): https://github.com/maltekrack/NLvib (the
% file SRC/HB_residual.m is all this script calls).  Run from the repository root with Octave
% (tested with GNU Octave 7.3):
%
%     octave --no-gui --eval "addpath('/path/to/NLvib/SRC'); run('benchmarks/peers/nlvib_epmc.m')"
%
% It writes docs/data/nlvib_epmc_ground.csv and docs/data/nlvib_epmc_between.csv with the
% columns a, omega, D (modal amplitude with a^2 = sum_h Q_h^H M Q_h, frequency in rad/s, modal
% damping ratio).
%
% The systems (unit masses; Jenkins element = NLvib 'elasticDryFriction', a spring k_t behind a
% slider of force F_s; NLvib marches its slider from rest over two periods, ours centres the
% Masing state: for the zero-mean motion of a mode both give the same periodic force):
%   ground : K = [2 -1; -1 2], C = 0.01 K, Jenkins (k_t = 1, F_s = 0.1) from DOF 1 to the ground.
%   between: K = [2 -1 0; -1 2 -1; 0 -1 1], C = 0.004 K, Jenkins (k_t = 1, F_s = 0.05) between
%            DOFs 1 and 2.
% Both: first mode, H = 7, N = 1024 samples per period, 25 amplitudes log-spaced over
% [1e-2, 1e1].  Each amplitude is solved by Newton on HB_residual with log10(a) held fixed
% (|R| < 1e-12), from the previous amplitude's solution (4 substeps in between).

1;

function X = newton_fixed(X, fun)
  for it = 1:40
    [R, dR] = fun(X);
    if norm(R) < 1e-12
      return;
    end
    X(1:end-1) = X(1:end-1) - dR(:, 1:end-1) \ R;
  end
  [R, dR] = fun(X);
  if norm(R) > 1e-9
    error('Newton did not converge: |R| = %g', norm(R));
  end
end

function run_case(outdir, name, M, C, K, w, kt, fs, H, N, amps)
  n = size(M, 1);
  sys.M = M; sys.D = C; sys.K = K;
  sys.nonlinear_elements = {struct('type', 'elasticDryFriction', 'stiffness', kt, ...
      'friction_limit_force', fs, 'force_direction', w, 'islocal', 1, 'ishysteretic', 1)};
  % stuck linear mode, mass-normalised
  [V, L] = eig(K + kt * (w * w'), M);
  [lam, i] = sort(diag(L)); phi = V(:, i(1)); phi = phi / sqrt(phi' * M * phi);
  [~, inorm] = max(abs(phi)); phi = phi * sign(phi(inorm));
  om = sqrt(lam(1)); del = phi' * C * phi / (2 * om);
  Psi = zeros((2 * H + 1) * n, 1); Psi(n + (1:n)) = phi;
  X = [Psi; om; del; log10(amps(1))];
  out = zeros(numel(amps), 3);
  fun = @(X) HB_residual(X, sys, H, N, 'NMA', inorm, 1);
  for j = 1:numel(amps)
    if j == 1
      steps = log10(amps(1));
    else
      steps = linspace(log10(amps(j - 1)), log10(amps(j)), 5)(2:end);
    end
    for s = steps
      X(end) = s;
      X = newton_fixed(X, fun);
    end
    out(j, :) = [10^X(end), X(end - 2), X(end - 1)];
  end
  fid = fopen(fullfile(outdir, ['nlvib_epmc_' name '.csv']), 'w');
  fprintf(fid, '# NLvib 1.3 EPMC (benchmarks/peers/nlvib_epmc.m): H = %d, N = %d\n', H, N);
  fprintf(fid, 'a,omega,D\n');
  fprintf(fid, '%.17g,%.17g,%.17g\n', out');
  fclose(fid);
  printf('%s: %d amplitudes, omega %.6f .. %.6f, D %.6g .. %.6g\n', name, numel(amps), ...
         min(out(:, 2)), max(out(:, 2)), min(out(:, 3)), max(out(:, 3)));
end

outdir = fullfile(fileparts(mfilename('fullpath')), '..', '..', 'docs', 'data');
amps = logspace(-2, 1, 25);
K2 = [2 -1; -1 2];
run_case(outdir, 'ground', eye(2), 0.01 * K2, K2, [1; 0], 1.0, 0.1, 7, 1024, amps);
K3 = [2 -1 0; -1 2 -1; 0 -1 1];
run_case(outdir, 'between', eye(3), 0.004 * K3, K3, [1; -1; 0], 1.0, 0.05, 7, 1024, amps);
