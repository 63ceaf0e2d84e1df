#!/usr/bin/env bash
# Installs every Debian 12 package that unisph's build, tests and plots need. Idempotent: only
# missing packages are installed (apt-get update runs only then). Works as root or with sudo.
# nvcc is not a Debian 12 package: where the CUDA toolkit is installed (/usr/local/cuda), the
# build uses it; without it unisph builds and tests its CPU policies.
set -euo pipefail

packages=(
  g++ cmake ninja-build pkg-config        # toolchain (CMake >= 3.25: Debian 12 has 3.25.1)
  libtbb-dev                              # the par policy (oneTBB)
  libgtest-dev libgmock-dev               # tests
  libbenchmark-dev                        # bench/
  libopenvdb-dev                          # bench/levelset only: OpenVDB's meshToLevelSet beside ours
                                          # (6 MB, installed in 2 s here; without it the bench skips it)
  libcli11-dev                            # the command line
  libtomlplusplus-dev                     # case files
  libopenmpi-dev openmpi-bin              # MPI: the communication layer (include/unisph/comm/) and its tests
  clang libclang-rt-14-dev                # the asan preset and the libFuzzer targets
  python3 python3-matplotlib python3-vtk9 # plots, reading output back with VTK (/usr/bin/python3)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
