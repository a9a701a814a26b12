#!/usr/bin/env bash
# Downstream-package test (ctest test downstream_package): installs workspace_proximity into an
# install space and builds test/downstream/ (a user's package) against it with catkin, then
# runs its two programs. Usage: test/downstream/run.sh SOURCE_DIR BUILD_DIR INSTALL_PREFIX
# When INSTALL_PREFIX lies inside BUILD_DIR (scripts/build configures BUILD_DIR/.install: a dot
# folder, which roslaunch's file search skips, so the installed launch files never shadow the
# source's), the existing build is installed there; otherwise (a user's prefix such as /usr/local, never written by a test)
# the package is configured and built afresh into a temporary install space.
set -euo pipefail
export PATH="/usr/bin:/bin:${PATH}"
src="$1"
build="$2"
prefix="$3"
work="$(mktemp -d /tmp/wp_downstream.XXXXXX)"
trap 'rm -rf "${work}"' EXIT
if [[ "${prefix}" == "${build}"/* ]]; then
  cmake --install "${build}" >"${work}/install.log" 2>&1 || { tail -30 "${work}/install.log"; exit 1; }
else
  prefix="${work}/install"
  cmake -S "${src}" -B "${work}/build" -DCMAKE_BUILD_TYPE=Release -DCATKIN_ENABLE_TESTING=OFF \
    -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCMAKE_INSTALL_PREFIX="${prefix}" >"${work}/install.log" 2>&1
  make -C "${work}/build" -j"$(nproc)" install >>"${work}/install.log" 2>&1 || { tail -30 "${work}/install.log"; exit 1; }
fi
# A fresh shell environment, as a user's: only the install space on top of the system's ROS.
env -i HOME="${work}" PATH="/usr/bin:/bin" bash -c '
  set -e
  set +u; source "$1/setup.bash"; set -u
  cmake -S "$2/test/downstream" -B "$3/downstream" -DPYTHON_EXECUTABLE=/usr/bin/python3 >"$3/downstream.log" 2>&1 \
    || { tail -30 "$3/downstream.log"; exit 1; }
  make -C "$3/downstream" >>"$3/downstream.log" 2>&1 || { tail -30 "$3/downstream.log"; exit 1; }
  "$3/downstream/devel/lib/wp_downstream_check/use_core"
  "$3/downstream/devel/lib/wp_downstream_check/use_monitor"
' bash "${prefix}" "${src}" "${work}"
