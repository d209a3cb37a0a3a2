# The environment of every job this Snakemake starts (issue 25 part 7), set once here.
#
# Threads: every job runs on the threads its rule declares (`threads:`; every rule here declares
# 1). Snakemake itself sets OMP_NUM_THREADS, OPENBLAS_NUM_THREADS, MKL_NUM_THREADS,
# GOTO_NUM_THREADS, VECLIB_MAXIMUM_THREADS and NUMEXPR_NUM_THREADS to the job's threads for every
# script job; it does not set numba's pool size, which would default to the machine's cores. The
# package's numba kernels are serial (no parallel=True), so one thread is all a job can use
# whatever it declares. scipy.fft runs on one worker unless told otherwise (signal/kurtogram.py
# no longer asks for all cores).
#
# Memory: the analysis jobs allocate and free arrays of the record's length (3-7 MB at 100
# revolutions) thousands of times; glibc returned each to the kernel (mmap/munmap, or a trimmed
# heap) and the kernel zeroed fresh pages for the next: 0.04 system-CPU s per envelope spectrum,
# about a sixth of the sweep's CPU was system time. Blocks below 32 MB (glibc's largest mmap
# threshold) now come from the heap, which keeps up to 256 MB of freed memory: the same numbers,
# 12x fewer page faults (benchmarks/sweep_cost.py, docs/benchmarks.md).
#
# tests/test_workflow_jobenv.py runs a job and checks its environment.
#
# These variables are set here, never read from the user's environment (hence no `envvars:`
# directive, which asserts variables the caller must provide); jobs on a cluster parse this file
# again and get the same values.
import os

JOB_ENVIRONMENT = {
    "NUMBA_NUM_THREADS": "1",
    "MALLOC_MMAP_THRESHOLD_": str(32 * 1024 * 1024),
    "MALLOC_TRIM_THRESHOLD_": str(256 * 1024 * 1024),
}
os.environ.update(JOB_ENVIRONMENT)
