# Sourced by the other scripts: one place for paths and the ROS-friendly environment.
# /usr/bin first: python3 on PATH may be a pyenv interpreter without ROS's modules.
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
WP_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WP_BUILD="${WP_BUILD_DIR:-${WP_ROOT}/build}"
export WP_ROOT WP_BUILD
