#!/usr/bin/env bash
# Installs the Debian 12 packages romp builds against, only those missing. Idempotent; runs as root
# or through sudo. The CUDA toolkit is not a Debian package: when nvcc is present (on PATH or in
# /usr/local/cuda) the CUDA backend is built, otherwise romp builds for the CPU alone.
set -euo pipefail

packages=(
  build-essential cmake ninja-build git pkg-config python3 python3-venv python3-yaml
  libeigen3-dev libgtest-dev libhdf5-dev libcli11-dev libtomlplusplus-dev
  libfmt-dev libspdlog-dev nlohmann-json3-dev libtorch-dev openmpi-bin
  clang libclang-rt-14-dev clang-format-14
)

missing=()
for package in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} Debian packages are installed"
  exit 0
fi

if [ "$(id -u)" -eq 0 ]; then
  as_root=()
elif command -v sudo >/dev/null 2>&1; then
  as_root=(sudo)
else
  echo "setup: need root or sudo to install: ${missing[*]}" >&2
  exit 1
fi

echo "setup: installing ${missing[*]}"
"${as_root[@]}" apt-get update -qq
"${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
