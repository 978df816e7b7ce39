#!/usr/bin/env bash
# Installs Debian packages when missing. Usage: ensure-debian.sh PURPOSE PACKAGE...
# (headless OpenGL for the renderer: EGL + Mesa llvmpipe; Chromium for the tileset page's check).
set -euo pipefail
purpose=$1
shift
missing=()
for pkg in "$@"; do
  dpkg -s "$pkg" >/dev/null 2>&1 || missing+=("$pkg")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "installing Debian packages for $purpose: ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
  echo "not root: run 'sudo apt-get install ${missing[*]}' and retry" >&2
  exit 1
fi
apt-get update -qq
DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
