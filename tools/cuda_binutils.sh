#!/usr/bin/env bash
# Prints the folder of a cuobjdump and nvdisasm for reading the build's SASS (build.kernel_resources checks how
# many loads the streaming kernels issue before a store). The CUDA toolkit's own are used where it has them;
# a minimal toolkit (nvcc and ptxas alone, as on CI) gets NVIDIA's from PyPI in a virtual environment.
# Idempotent: an environment that already holds the pinned version is reused.
#
#   ROMP_CUDA_BINUTILS_VERSION   the PyPI version (default 13.5.37: it reads sm_90 objects of nvcc 12 and 13)
#   ROMP_CUDA_BINUTILS_VENV      where the environment lives (default: a per-user cache)
set -euo pipefail
toolkit_bin="$(dirname "$(readlink -f "$(command -v nvcc || echo /usr/local/cuda/bin/nvcc)")")"
if [ -x "$toolkit_bin/cuobjdump" ] && [ -x "$toolkit_bin/nvdisasm" ]; then
  echo "$toolkit_bin"
  exit 0
fi

version="${ROMP_CUDA_BINUTILS_VERSION:-13.5.37}"
venv="${ROMP_CUDA_BINUTILS_VENV:-${XDG_CACHE_HOME:-$HOME/.cache}/romp/cuda-binutils-$version}"
if ! [ -x "$venv/bin/cuobjdump" ] || ! [ -x "$venv/bin/nvdisasm" ]; then
  echo "cuda_binutils: installing cuobjdump and nvdisasm $version from PyPI into $venv (6 MB)" >&2
  rm -rf "$venv"
  /usr/bin/python3 -m venv "$venv"
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check --no-cache-dir \
    "nvidia-cuda-cuobjdump==$version" "nvidia-cuda-nvdisasm==$version" >&2
  installed="$("$venv/bin/python" -c "import nvidia, os; print(os.path.join(nvidia.__path__[0], 'cu13', 'bin'))")"
  for tool in cuobjdump nvdisasm; do
    chmod +x "$installed/$tool"
    ln -sf "$installed/$tool" "$venv/bin/$tool"
  done
fi
echo "$venv/bin"
