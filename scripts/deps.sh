#!/usr/bin/env bash
# Installs exoid's Debian 12 build and run dependencies when any is missing.
# Idempotent and fast when everything is present (one dpkg query, no network).
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libgtest-dev libbenchmark-dev
  libmujoco-dev libqhull-dev libgl-dev libopengl-dev
  liburdfdom-dev
  libosmesa6-dev libgl1-mesa-dri ffmpeg zlib1g-dev
  nlohmann-json3-dev libcli11-dev libtomlplusplus-dev
  libpagmo-dev
  python3-matplotlib python3-numpy python3-dev pybind11-dev python3-pytest
  strace
  slurm-wlm
)

# Optional groups: --with-fuzz (clang and its libFuzzer runtime, for scripts/fuzz.sh).
for arg in "$@"; do
  case "$arg" in
    --with-fuzz) PACKAGES+=(clang-14 libclang-rt-14-dev) ;;
    *) echo "scripts/deps.sh: unknown option '$arg' (known: --with-fuzz)" >&2; exit 2 ;;
  esac
done

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
