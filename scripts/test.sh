#!/usr/bin/env bash
# Every test on a fresh Debian 12 machine: set up, build, run ctest (GL tests once per backend:
# EGL, OSMesa, the EGL device platform, GLFW under xvfb; the Python module's pytest and Dask suite as
# python.pytest), then everything but Python again built with
# ASan + UBSan: CPU tests with leak detection, GL tests on EGL without it (drivers keep allocations).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh build
(cd build && ctest --output-on-failure -j2)
scripts/setup.sh build-asan -DNURBSGL_SANITIZE=ON
# Under the sanitizers, in one ctest run so the two cores stay busy:
# - the property sweeps and printout benchmarks (test suite "sweep", tests/test_suites.h) and the CLI's
#   option sweep (label "sweep", 424 runs: 3.5 minutes under ASan) are left out: they ran above, and
#   under ASan they cost minutes on code the other cases reach;
# - GL programs run once, on EGL (the other backends and the debug context ran above), without leak
#   detection (set per test);
# - the CLI's clearance switches that pick another reduction block, fan-out or upper bound, and the
#   generated docs/cli.md, are left out: the GL unit tests run those passes under ASan;
# - the tessellation and ray-casting programs skip their sweeps over every shared model, and the CLI's
#   tessellate and deviation tests are CPU code those programs cover; the readers' own shared-model
#   tests (nurbs_io_tests[shared]) still run.
(cd build-asan && ctest --output-on-failure -j2 -LE sweep \
  -E "glfw|osmesa|egl-device|egl-debug|cli\.(tessellate|deviation|doc$|clearance_paper_(reduce_block|compact_fanout|gpu_upper))|^(tess|ray)_tests\[shared\]$")
