#!/usr/bin/env bash
# rosyhatch set-up: installs missing Debian packages, extracts the sample meshes,
# configures and builds, then either renders the default scene or runs every test.
#
#   tools/setup.sh render   # set-up + render scenes/bunny.yaml, prints the image path
#   tools/setup.sh test     # set-up + the whole test suite (ctest), then the sanitizer
#                           # and fuzzing phase (tools/ci-extra.sh; ROSY_CI_EXTRA=0 skips it)
#
# Idempotent: a second run with nothing changed only checks and re-runs the last step.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$here"
mode=${1:-render}
build=${ROSY_BUILD_DIR:-$here/build}
jobs=${ROSY_JOBS:-2}

packages=(cmake g++ ninja-build pkg-config libembree-dev libopenimageio-dev openimageio-tools
          libopenexr-dev libeigen3-dev libopenmesh-dev libyaml-cpp-dev libtbb-dev libcli11-dev
          libgtest-dev libbenchmark-dev libcgal-demo libsuitesparse-dev libopenblas-dev
          librsvg2-bin clang-14 libclang-rt-14-dev libfmt-dev nlohmann-json3-dev
          libcpp-httplib-dev libpng-dev libjs-three chromium chromium-driver python3-selenium)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# Sample meshes from Debian's CGAL demo data (never committed: data/ is git-ignored).
meshes=(bunny00.off armadillo.off fandisk.off elephant.off camel.off ChineseDragon-10kv.off double-torus-example.off
        head.off mannequin-devil.off triceratops.off couplingdown.off femur.off three_peaks.off
        elephant-with-holes.off lion-head.off man.off homer.off hand.off sphere.ply pig.stl helmet.off)
mkdir -p data/meshes
need=()
for m in "${meshes[@]}"; do [ -s "data/meshes/$m" ] || need+=("data/meshes/$m"); done
if [ ${#need[@]} -gt 0 ]; then
  echo "setup: extracting ${#need[@]} sample meshes into data/meshes"
  tar -xzf /usr/share/doc/libcgal-dev/data.tar.gz -C data/meshes --strip-components=2 "${need[@]}"
fi

if [ ! -f "$build/build.ninja" ]; then
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$build" -j "$jobs"

case "$mode" in
  render)
    mkdir -p out
    "$build/cli/rosyhatch" render scenes/bunny.yaml -o out/bunny.png
    echo "setup: rendered $here/out/bunny.png"
    ;;
  test)
    (cd "$build" && ctest --output-on-failure -j "$jobs")
    # Then the ASan + UBSan tree: the test suite under the sanitizers, every past fuzz
    # crasher and seed replayed, 60 s of fuzzing per harness (tools/ci-extra.sh; part of
    # CI). ROSY_CI_EXTRA=0 skips it for a quick local run.
    [ "${ROSY_CI_EXTRA:-1}" = 0 ] || tools/ci-extra.sh
    ;;
  *)
    echo "usage: tools/setup.sh render|test" >&2
    exit 2
    ;;
esac
