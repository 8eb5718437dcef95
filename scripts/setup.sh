#!/usr/bin/env bash
# Installs what argil needs to build and to run on Mesa's software Vulkan (lavapipe):
# the Vulkan loader, lavapipe, the Khronos validation layer, the system shaderc/glslang
# (so build.rs links them in seconds instead of compiling shaderc from C++), and Xvfb for
# windowed tests (with libXtst and python3, which move the pointer in one), and
# assimp-testmodels, whose Khronos glTF sample models (good and broken) tests/gltf.rs
# loads. Idempotent: does nothing when everything is present.
set -euo pipefail

packages=(
  libvulkan1 mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  libshaderc-dev glslang-dev spirv-tools
  xvfb xauth libxkbcommon-x11-0 libxcursor1 libxrandr2 libxi6 libx11-xcb1 libxtst6 python3
  pkg-config
  assimp-testmodels
)

if ! command -v dpkg-query >/dev/null 2>&1 || ! command -v apt-get >/dev/null 2>&1; then
  echo "argil setup: this is not a Debian/Ubuntu system." >&2
  echo "Install by hand: a Vulkan 1.3 loader and driver (Mesa lavapipe works), the Khronos" >&2
  echo "validation layer, and either system shaderc/glslang or build with" >&2
  echo "'--features shaderc-from-source'. Then run 'cargo build --release'." >&2
  exit 0
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "argil setup: installing ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then sudo="sudo"; else
    echo "argil setup: need root or sudo to install: ${missing[*]}" >&2; exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -q
$sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
