#!/usr/bin/env bash
# Installs everything caustica needs to build, render and test on Debian 12 (bookworm).
# Idempotent: packages already present are left alone. Runs as root or through sudo.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  glslang-dev glslang-tools spirv-tools
  libglm-dev libtinygltf-dev nlohmann-json3-dev
  libglfw3-dev libimgui-dev xvfb
  libopenimageio-dev openimageio-tools
  libgtest-dev libgmock-dev
  libembree-dev glmark2-data libcgal-demo assimp-testmodels
  clang libclang-rt-14-dev
  python3 python3-matplotlib
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  "$(dirname "$0")/fetch-models.sh"
  exit 0
fi

sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
echo "install-deps: installing ${missing[*]}"
"${sudo_cmd[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
"$(dirname "$0")/fetch-models.sh"
