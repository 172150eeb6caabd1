"""The default FRF (``python3 -m hbm``'s solve and peak) timed in-process, with a fingerprint of its bits.

Prints the median wall time of ``REPEATS`` solves, the number of points, the peak (repr, all
digits) and a SHA-256 prefix of the points' omega, amplitude and residual arrays, so two trees can
be compared for time and for bit-identity with one command each::

    PYTHONPATH=OLD_TREE python3 benchmarks/bench_default_frf.py
    PYTHONPATH=NEW_TREE python3 benchmarks/bench_default_frf.py

(``docs/performance.md``, "One balance").  Works on trees from before and after the re-layout.
"""

from __future__ import annotations

import hashlib
import statistics
import sys
import time
import warnings

from hbm import frequency_response

try:
    from hbm.cli.cases import default_case
except ImportError:  # a tree from before the command line had its own package
    from hbm.cli.cases import default_case

REPEATS = 15


def main(repeats: int = REPEATS) -> str:
    warnings.simplefilter("ignore", DeprecationWarning)
    case = default_case()
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        frf = frequency_response(case.blade, case.element, omega_range=case.omega_range)
        pk = frf.peak()
        times.append(time.perf_counter() - t)
    digest = hashlib.sha256(frf.omega.tobytes() + frf.amplitude.tobytes() + frf.residual_norm.tobytes())
    line = (f"median {statistics.median(times) * 1e3:.2f} ms over {len(times)}; points {len(frf)}; "
            f"peak {pk.omega!r} rad/s {pk.amplitude!r} m; sha256 {digest.hexdigest()[:16]}")
    print(line)
    return line


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else REPEATS)
