#!/usr/bin/env bash
# Prepares a fresh Debian 12 machine for camdyn and builds one CMake preset:
#   scripts/setup.sh [PRESET [TARGET...]]   PRESET: release (default), ci, debug, asan, fuzz
# With TARGETs only those are built (the quickstart builds just `camdyn`).
# Only the packages that are missing are installed, so a second run neither
# needs root nor touches the network.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

preset="${1:-release}"
targets=("${@:2}")
packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libsundials-dev libnlopt-cxx-dev libnlopt-dev libceres-dev
  coinor-libclp-dev libdxflib-dev nlohmann-json3-dev libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev
  gnuplot-nox python3 python3-numpy python3-scipy time
  pybind11-dev python3-dev python3-pytest python3-matplotlib python3-pandas
  libopenmpi-dev openmpi-bin chromium
)
# The test presets also check formatting and run clang-tidy (scripts/check_format.sh, check_tidy.sh).
[[ "$preset" == release ]] || packages+=(clang-format clang-tidy)
# The asan and fuzz presets build with clang 14, the libFuzzer targets among
# them (docs/fuzzing.md).
[[ "$preset" != asan && "$preset" != fuzz ]] || packages+=(clang-14 libfuzzer-14-dev libclang-rt-14-dev)

if ! command -v dpkg-query >/dev/null 2>&1; then
  echo "setup: dpkg-query not found; this script supports Debian 12 only." >&2
  echo "setup: install these packages (or their equivalents) by hand: ${packages[*]}" >&2
  exit 1
fi

missing=()
for package in "${packages[@]}"; do
  status="$(dpkg-query -W -f='${Status}' "$package" 2>/dev/null || true)"
  [[ "$status" == "install ok installed" ]] || missing+=("$package")
done

if ((${#missing[@]} > 0)); then
  echo "setup: installing ${missing[*]}" >&2
  if [[ "$(id -u)" -eq 0 ]]; then
    as_root=()
  elif command -v sudo >/dev/null 2>&1; then
    as_root=(sudo)
  else
    echo "setup: installing packages needs root and sudo is not available;" >&2
    echo "setup: as root, run: apt-get install -y --no-install-recommends ${missing[*]}" >&2
    exit 1
  fi
  # sudo resets the environment, so the variable is passed through env.
  "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update
  "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive \
    apt-get install -y --no-install-recommends "${missing[@]}"
else
  echo "setup: all ${#packages[@]} packages already installed" >&2
fi

echo "setup: configuring and building preset '$preset'" >&2
cmake --preset "$preset"
if ((${#targets[@]} > 0)); then
  cmake --build --preset "$preset" --target "${targets[@]}"
else
  cmake --build --preset "$preset"
fi
