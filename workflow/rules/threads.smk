# Every job runs on the threads its rule declares (`threads:`; every rule here declares 1).
# Snakemake itself sets OMP_NUM_THREADS, OPENBLAS_NUM_THREADS, MKL_NUM_THREADS, GOTO_NUM_THREADS,
# VECLIB_MAXIMUM_THREADS and NUMEXPR_NUM_THREADS to the job's threads for every script job; it
# does not set numba's pool size, which would default to the machine's cores. It is set here,
# once, for every job this Snakemake starts: the package's numba kernels are serial (no
# parallel=True), so one thread is all a job can use whatever it declares. scipy.fft runs on one
# worker unless told otherwise (signal/kurtogram.py no longer asks for all cores).
# tests/test_workflow_threads.py runs a job and checks its environment (issue 25 part 7).
import os

os.environ["NUMBA_NUM_THREADS"] = "1"
