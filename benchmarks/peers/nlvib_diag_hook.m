% nlvib_diag_hook.m: frictiondamp's diagnostic hook for benchmarks/peers/nlvib_ex07.m (not part of
% NLvib). It logs one line per corrector solve of NLvib's continuation, accepted or not, to the file
% named by the environment variable NLVIB_DIAG_LOG: istep, Om, norm of the extended residual,
% fsolve's exit flag, fsolve's iterations, the step size ds and NLvib's failure counter.
% NLvib does not call it by itself: the local copy of NLvib's SRC/solve_and_continue.m used for
% docs/data/nlvib_ex07*_attempts.csv got, right after the corrector's fsolve call (before
% "ACCEPT/REJECT POINT"), the lines
%     if exist('nlvib_diag_hook', 'file')
%         nlvib_diag_hook(istep, Xtmp, Rext, iEx, output, Sopt.ds, ierr);
%     end
% and this directory on the path (NLVIB_DIAG_DIR=benchmarks/peers).
function nlvib_diag_hook(istep, Xtmp, Rext, iEx, output, ds, ierr)
  f = getenv('NLVIB_DIAG_LOG');
  if isempty(f), return; end
  fid = fopen(f, 'a');
  fprintf(fid, '%d,%.17g,%.6g,%d,%d,%.6g,%d\n', istep, Xtmp(end), norm(Rext), iEx, output.iterations, ds, ierr);
  fclose(fid);
end
