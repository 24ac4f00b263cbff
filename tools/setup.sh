#!/usr/bin/env sh
# Installs the system packages brdfpaint needs on a fresh Debian or Ubuntu machine, if they
# are missing: Mesa's EGL and software GL driver for headless rendering, and with --viewer
# the X libraries and Xvfb for the window and its tests. As root it installs them; otherwise
# it prints the one command to run and fails.
set -eu
# --gltf-validator: node and npm (system packages), then the Khronos glTF validator into
# tools/gltf-validator/node_modules, which tests/export.rs runs.
if [ "${1:-}" = "--gltf-validator" ]; then
  if ! command -v npm >/dev/null 2>&1; then
    if [ "$(id -u)" -ne 0 ] || ! command -v apt-get >/dev/null 2>&1; then
      echo "setup: node and npm missing; install them (Debian: sudo apt-get install nodejs npm)" >&2
      exit 1
    fi
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq nodejs npm
  fi
  cd "$(dirname "$0")/gltf-validator"
  npm ci --no-audit --no-fund
  exit 0
fi
pkgs="libegl1 libegl-mesa0 libgl1-mesa-dri libgles2"
if [ "${1:-}" = "--viewer" ]; then
  pkgs="$pkgs libgl1 libglx-mesa0 libx11-xcb1 libxcursor1 libxrandr2 libxi6 libxkbcommon-x11-0 xvfb xauth x11-apps"
fi
if ! command -v dpkg >/dev/null 2>&1; then
  echo "setup: not a Debian or Ubuntu system; install Mesa's EGL and its software GL driver (llvmpipe) yourself" >&2
  exit 0
fi
need=""
for p in $pkgs; do
  dpkg -s "$p" >/dev/null 2>&1 || need="$need $p"
done
[ -z "$need" ] && exit 0
if [ "$(id -u)" -ne 0 ]; then
  echo "setup: missing system packages; run: sudo apt-get install$need" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
# shellcheck disable=SC2086
apt-get install -y -qq $need
