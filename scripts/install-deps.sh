#!/usr/bin/env bash
# Installs the Debian 12 packages gistream builds and runs with. Idempotent:
# installs only what is missing; uses sudo when not root.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config ninja-build
  libgrpc++-dev libprotobuf-dev protobuf-compiler protobuf-compiler-grpc libabsl-dev
  libegl-dev libgl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri
  libglm-dev libopenimageio-dev openimageio-tools libopenexr-dev libtinygltf-dev nlohmann-json3-dev
  libjpeg62-turbo-dev libpng-dev libembree-dev prometheus-cpp-dev libavcodec-dev libavutil-dev
  libgtest-dev libgmock-dev
  libboost-dev  # Boost.Beast (header-only) for gistream-web
  chromium nodejs  # the viewer test (tests/web) drives headless Chromium through puppeteer-core
  python3 python3-grpcio python3-protobuf  # the Python client package (python/) and its test
  openssl python3-yaml  # test certificates (scripts/dev_certs.sh), the deployment test (tests/deploy)
  clang libclang-rt-14-dev  # CI's sanitizer and libFuzzer build (scripts/ci-sanitizers.sh), the thread_safety_analysis test
  clang-format  # the `format` test and `make format` (.clang-format)
  libmeshoptimizer-dev  # proxy geometry for the GI passes (server/scene/proxies/proxy_levels.h)
  haproxy  # the fleet test (tests/deploy/fleet_test.py): three servers behind a real balancer
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

# npm for the viewer test's puppeteer-core: Debian ships it apart from
# nodejs; a nodejs from elsewhere (NodeSource) brings its own.
command -v npm >/dev/null 2>&1 || missing+=(npm)
# GISTREAM_NO_TEST_DEPS=1 (image builds): leave out what only tests need.
if [ "${GISTREAM_NO_TEST_DEPS:-0}" = 1 ]; then
  kept=()
  for p in "${missing[@]}"; do
    case "$p" in chromium|nodejs|npm|clang|libclang-rt-14-dev|clang-format|haproxy) ;; *) kept+=("$p") ;; esac
  done
  missing=("${kept[@]+"${kept[@]}"}")
fi

# GISTREAM_CONTAINER_DEPS=1: also podman and debootstrap, for `make image`
# and deploy/smoke_test.sh (deploy/README.md: the base image is imported
# from a debootstrap root).
if [ "${GISTREAM_CONTAINER_DEPS:-0}" = 1 ]; then
  for p in podman debootstrap runc; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
fi

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1
  fi
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
