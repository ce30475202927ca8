#!/usr/bin/env bash
# Run here (Debian 12): fills the ignored folder .device/ with what a bare GPU machine lacks to
# build romp against PyTorch's LibTorch: Eigen, GoogleTest, CLI11, toml++, nlohmann-json, fmt,
# spdlog and HDF5, from Debian's packages, unpacked under .device/root (headers, libraries and
# CMake package files), and HDF5's dependencies that such a machine lacks under .device/extra. Then
# call the device tool with carry [".device"] and the command
#   tools/device_run.sh
# which builds romp there, runs the tests, the benchmarks and CUDA-against-CPU runs, and leaves at
# most three files in $OUT.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
device_dir="$root/.device"

packages=(
  libeigen3-dev libgtest-dev libcli11-dev libtomlplusplus-dev libtomlplusplus3 nlohmann-json3-dev
  libfmt-dev libfmt9 libspdlog-dev libspdlog1.10
  libhdf5-dev libhdf5-103-1 libhdf5-hl-100 libsz2 libaec0
)

rm -rf "$device_dir"
mkdir -p "$device_dir/debs" "$device_dir/root"
(cd "$device_dir/debs" && apt-get download "${packages[@]}")
for deb in "$device_dir"/debs/*.deb; do
  dpkg-deb -x "$deb" "$device_dir/root"
done
rm -rf "$device_dir/debs"
# HDF5's own dependencies that a bare GPU machine lacks (seen on Ubuntu 24.04: the LDAP, SSH and
# Unicode libraries libcurl pulls in). They go to .device/extra, not onto the library path:
# device_run.sh links in only those the machine does not have, since shadowing the machine's own
# libraries (libcrypto, libz) breaks its Python and CMake.
extra_packages=(libldap-2.5-0 libssh2-1 libunistring2)
mkdir -p "$device_dir/extra-debs" "$device_dir/extra"
(cd "$device_dir/extra-debs" && apt-get download "${extra_packages[@]}")
for deb in "$device_dir"/extra-debs/*.deb; do
  dpkg-deb -x "$deb" "$device_dir/extra-debs/root"
done
find "$device_dir/extra-debs/root" -name "*.so.*" \( -type f -o -type l \) -exec cp -aL {} "$device_dir/extra/" \;
rm -rf "$device_dir/extra-debs"
# Only the shared C library of HDF5 is used; its static, C++ and Fortran variants are dead weight.
find "$device_dir/root" \( -name "libhdf5*.a" -o -name "libhdf5*fortran*" -o -name "libhdf5*cpp*" \) -delete

# Debian's library symlinks are absolute (/usr/lib/...); point them inside the unpacked tree.
lib="$device_dir/root/usr/lib/x86_64-linux-gnu"
find "$device_dir/root" -type l | while read -r link; do
  target="$(readlink "$link")"
  if [[ "$target" == /* ]]; then ln -sfn "$device_dir/root$target" "$link"; fi
done
echo "device_prepare: $(du -sh "$device_dir" | cut -f1) in $device_dir (libraries under ${lib#$root/})"
