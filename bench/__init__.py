"""The benchmarks (``make bench``). They time CPU seconds of the whole process, so the BLAS
libraries run single-threaded: an idle worker thread spinning after each call would otherwise be
counted (Dietmaier's row measured 2-3x slow for every contender, NumPy's and fkSGP's included).
The variables are read when NumPy loads its BLAS, which is why they are set here, before any
benchmark module imports NumPy."""

import os

for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")
