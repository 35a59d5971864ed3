#!/usr/bin/env bash
# hedra quick start for a Debian 12 machine: installs the Debian packages the
# build, tests and peer cross-checks need (only those missing; nothing is
# downloaded when all are present, and `apt-get update` runs only when
# something is missing), configures a Release build in build/ (Ninja when
# available), builds it, and runs the demo job.
#
# Works as root or through sudo; never prompts (DEBIAN_FRONTEND=noninteractive,
# apt-get -y), so it runs unattended in CI. Environment: HEDRA_JOBS sets the
# build parallelism (default: the number of processors).
set -euo pipefail

repo_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$repo_root"

packages=(
  build-essential cmake ninja-build
  libeigen3-dev                                  # the libraries
  libgtest-dev libgmock-dev libbenchmark-dev     # tests and benchmarks
  nlohmann-json3-dev libcli11-dev                # the hedra tool
  libqhull-dev                                   # the exact reference
  libccd-dev libfcl-dev libbullet-dev            # peers (HEDRA_WITH_PEERS)
  libmujoco-dev                                  # hedra as MuJoCo's narrowphase (tools/mujoco/)
  python3-matplotlib                             # plots
  pybind11-dev python3-dev python3-numpy python3-pytest  # the Python module (tools/python/) and its tests
  libjs-three                                    # three.js, embedded into `hedra view` pages
  chromium                                       # headless browser for the `hedra view` page tests
  pkgconf                                        # the pkg-config consumer test (tests/downstream)
)

say() { printf '==> %s\n' "$*"; }

is_installed() {
  # Captured rather than piped: with pipefail, grep -q exiting early could
  # fail the pipeline.
  local status
  status=$(dpkg -s "$1" 2>/dev/null) || return 1
  grep -qx 'Status: install ok installed' <<<"$status"
}

if command -v dpkg >/dev/null 2>&1; then
  missing=()
  for package in "${packages[@]}"; do
    is_installed "$package" || missing+=("$package")
  done
  if ((${#missing[@]} > 0)); then
    if [[ $(id -u) -eq 0 ]]; then
      as_root=()
    elif command -v sudo >/dev/null 2>&1; then
      as_root=(sudo)
    else
      echo "quickstart: missing packages (${missing[*]}) and neither root nor sudo to install them" >&2
      exit 1
    fi
    say "installing ${missing[*]}"
    ${as_root[@]+"${as_root[@]}"} env DEBIAN_FRONTEND=noninteractive apt-get update -q
    ${as_root[@]+"${as_root[@]}"} env DEBIAN_FRONTEND=noninteractive \
      apt-get install -y -q --no-install-recommends "${missing[@]}"
  else
    say "all Debian packages present"
  fi
else
  echo "quickstart: no dpkg here (not Debian?); install the equivalents of: ${packages[*]}" >&2
fi

# Keep the generator of an existing build/; otherwise prefer Ninja.
generator=()
if [[ ! -f build/CMakeCache.txt ]] && command -v ninja >/dev/null 2>&1; then
  generator=(-G Ninja)
fi
jobs=${HEDRA_JOBS:-$(nproc 2>/dev/null || echo 2)}

# The quick start builds the peer cross-checks too (libccd, FCL, Bullet);
# embedders leave HEDRA_WITH_PEERS off and depend on Eigen alone.
say "configuring build/ (Release, peers on)"
cmake -S . -B build ${generator[@]+"${generator[@]}"} -DCMAKE_BUILD_TYPE=Release -DHEDRA_WITH_PEERS=ON
say "building with $jobs jobs"
cmake --build build --parallel "$jobs"

say "build/bin/hedra hull tools/cli/data/demo_points.xyz"
build/bin/hedra hull tools/cli/data/demo_points.xyz
# The library's main job: contact, penetration and distance queries.
say "build/bin/hedra query scenes/demo.json"
build/bin/hedra query scenes/demo.json
