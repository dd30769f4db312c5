#!/usr/bin/env bash
# Installs everything caustica needs to build, render and test on Debian 12 (bookworm).
# Idempotent: packages already present are left alone. Runs as root or through sudo.
#
# Mesa's lavapipe comes from bookworm-backports (25.0.x): bookworm's own 22.3 has no ray tracing,
# and 25 has VK_KHR_acceleration_structure and VK_KHR_ray_query, which the exact-path graphs
# (caustics_raytraced.json, refraction_raytraced.json, the hybrids) need. Every other graph runs on
# either version. CAUSTICA_NO_BACKPORTS=1 keeps bookworm's Mesa.
#
# Slurm 22.05 and munge are for tests/slurm/slurm_test.sh, which starts its own munged, slurmctld
# and slurmd on localhost in a temporary folder (docs/cluster.md); nothing here configures or
# starts them. Under systemd, Debian enables their services: munge's starts with the key the
# package made, slurmctld's and slurmd's stay down without an /etc/slurm/slurm.conf; the test
# uses its own socket, key and ports, whatever runs.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  glslang-dev glslang-tools spirv-tools
  libglm-dev libtinygltf-dev nlohmann-json3-dev libdraco-dev libmeshoptimizer-dev
  libglfw3-dev libimgui-dev xvfb xdotool
  libopenexr-dev libstb-dev openimageio-tools
  libgtest-dev libgmock-dev
  libembree-dev glmark2-data libcgal-demo assimp-testmodels
  clang libclang-rt-14-dev lld
  python3 python3-matplotlib graphviz
  munge slurmctld slurmd slurm-client
)

sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
apt_install() {
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "$@"
}

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

# Mesa 25 or later: the ray-query lavapipe.
mesa_version="$(dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null || true)"
want_backports=0
if [ "${CAUSTICA_NO_BACKPORTS:-0}" != 1 ] &&
   ! dpkg --compare-versions "${mesa_version:-0}" ge 25; then
  want_backports=1
fi

if [ ${#missing[@]} -eq 0 ] && [ "$want_backports" -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present (mesa-vulkan-drivers $mesa_version)"
  "$(dirname "$0")/fetch-models.sh"
  exit 0
fi

if [ "$want_backports" -eq 1 ] &&
   ! grep -rqs 'bookworm-backports' /etc/apt/sources.list /etc/apt/sources.list.d/; then
  echo "install-deps: adding the bookworm-backports suite (for Mesa 25's ray-query lavapipe)"
  echo 'deb http://deb.debian.org/debian bookworm-backports main' |
    "${sudo_cmd[@]}" tee /etc/apt/sources.list.d/caustica-backports.list > /dev/null
fi

"${sudo_cmd[@]}" apt-get update -qq
if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  apt_install "${missing[@]}"
fi
if [ "$want_backports" -eq 1 ]; then
  echo "install-deps: installing mesa-vulkan-drivers from bookworm-backports"
  apt_install -t bookworm-backports mesa-vulkan-drivers
fi
"$(dirname "$0")/fetch-models.sh"
