#!/usr/bin/env bash
# SPDX-License-Identifier: AGPL-3.0-or-later
# Installs the Debian packages palpa needs, and only those that are missing.
# Idempotent: when everything is installed it prints one line and changes nothing.
# OpenBLAS (pthread build) takes over libblas.so.3 and liblapack.so.3 from the
# ATLAS that Ceres brings, by the priority of Debian's alternatives: CHOLMOD's
# supernodal factorizations run on it (`palpa --version` names the BLAS in use).
# clang (with its sanitizer runtimes) builds palpa: about 25% faster than g++
# for the Release build, and half the time for the ASan + UBSan build.
# ccache: the build uses it when present (see CMakeLists.txt), so a build in a
# fresh clone or worktree reuses what an earlier build of the same sources
# compiled.
# pybind11, numpy and pytest: the Python module (`make python`) and its tests.
# Open MPI spreads a cohort design over processes (mpirun, or srun on Slurm).
# Snakemake runs the subject pipeline (workflow/Snakefile); Chromium (and PIL,
# to look at its screenshots) opens the HTML reports in the tests.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config ccache
  clang libclang-rt-14-dev
  libeigen3-dev libsuitesparse-dev libtbb-dev
  libcgal-dev libgmp-dev libmpfr-dev libtet1.5-dev
  libcli11-dev nlohmann-json3-dev libfmt-dev libspdlog-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libceres-dev zlib1g-dev
  libopenmpi-dev openmpi-bin
  libopenblas0-pthread
  python3 python3-meshio
  python3-dev pybind11-dev python3-numpy python3-pytest
  calculix-ccx
  snakemake chromium python3-pil
)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  if [[ "$status" != "install ok installed" ]]; then
    missing+=("$p")
  fi
done

if (( ${#missing[@]} == 0 )); then
  echo "setup: all ${#packages[@]} Debian packages present"
  exit 0
fi

echo "setup: installing ${missing[*]}"
sudo_cmd=()
if (( EUID != 0 )); then
  if command -v sudo >/dev/null 2>&1; then
    sudo_cmd=(sudo)
  else
    echo "setup: error: packages are missing and this user is not root (no sudo either);" >&2
    echo "       install them as root: apt-get install ${missing[*]}" >&2
    exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"
