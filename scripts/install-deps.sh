#!/usr/bin/env bash
# Installs exactly the Debian 12 packages tridex needs to build, test and run its demo.
# Idempotent: installs only what is missing. Uses sudo when not root.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config git      # toolchain
  ccache                                    # compiler cache: rebuilds in CI and across git worktrees reuse objects
  libglm-dev                                # math (GLM)
  libopenmesh-dev                           # mesh I/O and half-edge checks (OpenMesh)
  libvulkan-dev vulkan-validationlayers     # Vulkan loader, headers, validation layer
  mesa-vulkan-drivers                       # lavapipe, the CPU Vulkan driver
  glslang-tools                             # GLSL -> SPIR-V at build time
  libstb-dev                                # stb_image_write for PNG
  nlohmann-json3-dev                        # report.json
  libcli11-dev                              # command line
  libglfw3-dev                              # windows and fullscreen on the wall (GLFW)
  libtbb-dev                                # oneTBB: the persistent task scheduler of the CPU Booleans, contouring, scan conversion
  libzstd-dev                               # zstd: compresses the sections of the .tdx model file
  libmeshoptimizer-dev                      # meshoptimizer: simplified levels of detail of the tile meshes
  libusb-1.0-0-dev                          # USB: detecting (and later driving) haptic devices (libusb-1.0)
  xvfb xauth                                # a virtual X server for the window smoke test
  xdotool                                   # real X mouse and key events (XTEST) for the mouse-stylus window test
  libgtest-dev libgmock-dev                 # tests
  libbenchmark-dev                          # benchmarks
  libopenvdb-dev libboost-dev               # OpenVDB level-set peer of `tridex bench --accuracy`; Boost.Math for `tridex study stats`
  gnuplot-nox                               # PNG plots of `tridex bench --accuracy`
  libenet-dev                               # device server link: ENet's reliable + unreliable channels over UDP, sequenced
  libsodium-dev                             # sealed datagram link: libsodium's Argon2id, BLAKE2b and XSalsa20-Poly1305 (never home-made crypto)
  openmpi-bin libopenmpi-dev                # Open MPI: the ranks of a cluster session (tridex run --cluster; a build without it builds the rest)
  universal-ctags                           # the layout test that measures function lengths (tests/layout/test_house_rules.cpp)
  clang libclang-rt-14-dev                  # the fuzz targets (tests/fuzz/, `fuzz` preset): clang 14 and its libFuzzer and sanitizer runtimes
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
$SUDO apt-get update
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
