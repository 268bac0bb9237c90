#!/usr/bin/env bash
# Installs exoid's Debian 12 build and run dependencies when any is missing.
# Idempotent and fast when everything is present (one dpkg query, no network).
# Usage: scripts/deps.sh [--main] [--with-fuzz] [--with-slurm] [--with-ccache]
#   --main        only what `exoid` and its report need (scripts/reproduce.sh)
#   (default)     also the tests', benchmarks' and Python module's packages (scripts/test.sh)
#   --with-fuzz   clang and its libFuzzer runtime, for scripts/fuzz.sh
#   --with-slurm  slurm-wlm, for the cluster path and its test (see experiments/SWEEP.md); its
#                 system services are left stopped and disabled: the test starts its own daemons
#   --with-ccache ccache, with which .ci/run shares object files between its configurations
set -euo pipefail

MAIN_PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libmujoco-dev libqhull-dev libgl-dev libopengl-dev
  liburdfdom-dev
  libosmesa6-dev libgl1-mesa-dri ffmpeg zlib1g-dev
  nlohmann-json3-dev libcli11-dev libtomlplusplus-dev
  python3-matplotlib python3-numpy
)
TEST_PACKAGES=(
  libgtest-dev libbenchmark-dev libpagmo-dev
  python3-dev pybind11-dev python3-pytest python3-cvxopt python3-pykdl
  strace
)

main_only=0 slurm=0
extra=()
for arg in "$@"; do
  case "$arg" in
    --main) main_only=1 ;;
    --with-fuzz) extra+=(clang-14 libclang-rt-14-dev) ;;
    --with-slurm) extra+=(slurm-wlm); slurm=1 ;;
    --with-ccache) extra+=(ccache) ;;
    *) echo "scripts/deps.sh: unknown option '$arg' (known: --main, --with-fuzz, --with-slurm, --with-ccache)" >&2; exit 2 ;;
  esac
done
PACKAGES=("${MAIN_PACKAGES[@]}")
((main_only)) || PACKAGES+=("${TEST_PACKAGES[@]}")
PACKAGES+=(${extra[@]+"${extra[@]}"})

missing=()
for p in "${PACKAGES[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done

if ((${#missing[@]} == 0)); then
  exit 0
fi

echo "exoid: installing missing Debian packages: ${missing[*]}" >&2
SUDO=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "exoid: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get -o DPkg::Lock::Timeout=600 update -qq
$SUDO apt-get -o DPkg::Lock::Timeout=600 install -y -qq --no-install-recommends "${missing[@]}"

# slurm-wlm's packages enable slurmd, slurmctld and munge; without a cluster's slurm.conf they only
# fail at boot. exoid needs the programs, not the services (a real cluster configures its own).
if ((slurm)) && [[ -d /run/systemd/system ]]; then
  $SUDO systemctl disable --now slurmd slurmctld munge >/dev/null 2>&1 || true
fi
