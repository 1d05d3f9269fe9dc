#!/usr/bin/env bash
# Every test on a fresh Debian 12 machine: set up, build, run ctest (GL tests once per backend:
# EGL, OSMesa, the EGL device platform, GLFW under xvfb), then everything again built with
# ASan + UBSan: CPU tests with leak detection, GL tests on EGL without it (drivers keep allocations).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh build
(cd build && ctest --output-on-failure -j2)
scripts/setup.sh build-asan -DNURBSGL_SANITIZE=ON
# Under the sanitizers the tessellation and ray-casting programs run without their sweeps over every
# shared model and without their few heavy cases (a minute or more each under ASan; they ran above);
# the readers' own shared-model tests (nurbs_io_tests[shared]) still run here.
(cd build-asan && ctest --output-on-failure -j2 -L cpu -E "^(tess_tests|ray_tests)")
heavy="*large case*,*proven bound holds*,*benchmark*,*exact shapes*,*counts fall*,*Table 3 style*"
build-asan/tests/nurbs/tessellation/tess_tests --test-suite-exclude=shared_models -tce="$heavy"
build-asan/tests/nurbs/raycast/ray_tests --test-suite-exclude=shared_models
# Under the sanitizers once, on EGL: they check our code, the other backends ran above.
# The CLI's tessellate and deviation tests are CPU code the programs above cover.
(cd build-asan && ASAN_OPTIONS=detect_leaks=0 ctest --output-on-failure -j2 -L "gl|cli" -E "glfw|osmesa|egl-device|cli\.(tessellate|deviation)")
