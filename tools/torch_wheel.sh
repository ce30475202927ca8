#!/usr/bin/env bash
# Installs PyPI's torch wheel (a CUDA build of LibTorch, the kind GPU machines use; it also runs on a
# machine without a GPU) into a virtual environment and prints the CMake folder of its LibTorch, for
# `-DTorch_DIR=...`. Idempotent: an environment that already holds the pinned version is reused.
#
#   ROMP_TORCH_WHEEL   the version installed (default: the one the H200 run used, 2.11.0)
#   ROMP_TORCH_VENV    where the environment lives (default: a per-user cache, so that repeated
#                      clones on one machine download it once)
set -euo pipefail
version="${ROMP_TORCH_WHEEL:-2.11.0}"
venv="${ROMP_TORCH_VENV:-${XDG_CACHE_HOME:-$HOME/.cache}/romp/torch-$version}"
python=/usr/bin/python3  # Debian's interpreter: the environment must not depend on a user's pyenv

installed() { "$venv/bin/python" -c "import torch, sys; sys.exit(torch.__version__.split('+')[0] != '$version')" 2>/dev/null; }

if ! installed; then
  echo "torch_wheel: installing torch==$version from PyPI into $venv (about 3 GB with its CUDA libraries)" >&2
  rm -rf "$venv"
  "$python" -m venv "$venv"
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check --no-cache-dir "torch==$version" >&2
  installed || { echo "torch_wheel: torch $version did not import from $venv" >&2; exit 1; }
fi
"$venv/bin/python" -c "import torch.utils, os; print(os.path.join(torch.utils.cmake_prefix_path, 'Torch'))"
