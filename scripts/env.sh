# Sourced by the other scripts: one place for paths and the ROS-friendly environment.
# /usr/bin first: python3 on PATH may be a pyenv interpreter without ROS's modules.
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
WP_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WP_BUILD="${WP_BUILD_DIR:-${WP_ROOT}/build}"
export WP_ROOT WP_BUILD

# A build folder, made with its CATKIN_IGNORE before cmake runs: catkin writes its own only
# after configuring, and catkin_lint (a test) must never see the compiler checks' executables
# of a build being configured beside it (scripts/test builds later stages in the background).
wp_build_dir() {
  mkdir -p "$1"
  touch "$1/CATKIN_IGNORE"
}
