#!/usr/bin/env bash
# Installs what building and testing mbrt needs on Debian 12 (bookworm).
# Skips apt entirely when every package is already installed.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libtbb-dev libgtest-dev libcli11-dev libpng-dev libembree-dev libopenexr-dev
  libtinygltf-dev nlohmann-json3-dev libstb-dev
  clang-14 libclang-rt-14-dev
  libopenmpi-dev openmpi-bin
  embree-tools
  python3-dev python3-numpy python3-pybind11 pybind11-dev python3-pytest python3-matplotlib
  python3-pip python3-setuptools python3-wheel python3-venv
  git ca-certificates
  python3-open3d blender  # embree_api/clients: Open3D and Cycles run on the libembree3 shim
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

sudo=()
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then
    sudo=(sudo)
  else
    echo "install-deps: missing packages (${missing[*]}) and not root (no sudo)" >&2
    exit 1
  fi
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update
"${sudo[@]}" apt-get install -y --no-install-recommends "${packages[@]}"
