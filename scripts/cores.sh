# SPDX-License-Identifier: Apache-2.0
# Sourced by the build and test scripts: `cores`, the processors this process may run on, for the
# compiler's and ctest's parallelism. GNU nproc also honours OMP_NUM_THREADS and OMP_THREAD_LIMIT,
# which are set to keep LibTorch and OpenBLAS at one thread, not the build: with OMP_NUM_THREADS=1 a
# cold `.ci/run` compiled on one of two cores and took 91 min.
cores=$(env -u OMP_NUM_THREADS -u OMP_THREAD_LIMIT nproc)
