#!/usr/bin/env bash
# Installs a build into a temporary prefix and renders an installed scene with the installed
# binary from an unrelated folder: nothing may depend on the source or build tree at run time.
#   tools/check_install.sh BUILD_DIR
set -euo pipefail
build=$(cd "${1:?usage: check_install.sh BUILD_DIR}" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
bin="$tmp/prefix/bin/hairtrace"
scenes="$tmp/prefix/share/hairtrace/scenes"
[ -x "$bin" ] || { echo "check_install: no $bin" >&2; exit 1; }
[ -f "$scenes/default.gltf" ] || { echo "check_install: no $scenes/default.gltf" >&2; exit 1; }
mkdir "$tmp/elsewhere"
cd "$tmp/elsewhere"
# No kernel folder, no source tree: the embedded kernels only.
env -u HAIRTRACE_KERNEL_DIR HAIRTRACE_CACHE_DIR=off "$bin" render "$scenes/default.gltf" -o out.png -o out.exr \
    --width 24 --height 32 --spp 1 --max-depth 2 --quiet
[ -s out.png ] && [ -s out.exr ] || { echo "check_install: the installed binary wrote no image" >&2; exit 1; }
echo "check_install: $bin rendered $scenes/default.gltf from $tmp/elsewhere"
