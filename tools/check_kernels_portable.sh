#!/usr/bin/env bash
# Compiles every kernel program with clang as strict OpenCL C for a generic SPIR target: the
# kernels must not lean on anything PoCL accepts but the standard does not.
#   usage: tools/check_kernels_portable.sh CLANG STD     (STD: CL1.2 or CL3.0)
set -euo pipefail
clang=${1:-clang}
std=${2:-CL1.2}
root=$(cd "$(dirname "$0")/.." && pwd)
status=0
for f in "$root"/kernels/stages/*.cl "$root"/kernels/*/*.cl; do
    [ -f "$f" ] || continue
    extra=()
    # OpenCL C 3.0 makes these optional; a CL3.0 device may leave them out, so do not assume them.
    [ "$std" = CL3.0 ] && extra=(-Xclang -cl-ext=-all)
    if ! "$clang" -x cl -cl-std="$std" -target spir64-unknown-unknown -Xclang -finclude-default-header \
         -fsyntax-only -cl-single-precision-constant -Werror -Wall -Wno-unused-function -Wno-unused-variable "${extra[@]}" "$f"; then
        echo "FAILED: $f ($std)"
        status=1
    fi
done
[ $status = 0 ] && echo "all kernels compile as strict $std for spir64"
exit $status
