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
# The render program is built with scene features switched off (host/render/features.cpp):
# compile it with every feature off too, so code that only one configuration reaches is checked.
off=()
# every switch of kernels/features.h's HT_FEATURE_SWITCHES list but the lobes (their combinations
# are compiled below)
for f in $(sed -n 's/^ *X(\([A-Z_]*\),.*/\1/p' "$root/kernels/features.h" | grep -v '^LOBE_'); do
    off+=("-DHT_FEATURE_$f=0")
done
[ ${#off[@]} -ge 10 ] || { echo "FAILED: could not read the feature list of kernels/features.h"; exit 1; }
# the render program's four builds (host/render/renderer.cpp)
render_programs=("$root/kernels/stages/trace.cl" "$root/kernels/stages/shade.cl" "$root/kernels/stages/intersect_shadow_afs.cl"
                 "$root/kernels/stages/lists.cl")
extra=()
[ "$std" = CL3.0 ] && extra=(-Xclang -cl-ext=-all)
if ! "$clang" -x cl -cl-std="$std" -target spir64-unknown-unknown -Xclang -finclude-default-header \
     -fsyntax-only -cl-single-precision-constant -Werror -Wall -Wno-unused-function -Wno-unused-variable \
     "${off[@]}" "${extra[@]}" "${render_programs[@]}"; then
    echo "FAILED: the render programs with scene features off ($std)"
    status=1
fi
# Meshes without textures: the one partial surface configuration.
if ! "$clang" -x cl -cl-std="$std" -target spir64-unknown-unknown -Xclang -finclude-default-header \
     -fsyntax-only -cl-single-precision-constant -Werror -Wall -Wno-unused-function -Wno-unused-variable \
     -DHT_FEATURE_MESHES=1 -DHT_FEATURE_TEXTURES=0 "${extra[@]}" "${render_programs[@]}"; then
    echo "FAILED: the render programs with meshes but no textures ($std)"
    status=1
fi
# Lobes (kernels/fiber/lobes.h): every combination, with every model and the AFS stage in, and with
# the other features off.
for lobes in "0 0" "0 1" "1 0"; do
    set -- $lobes
    for rest in "-DHT_FEATURE_INDIRECT_AFS=1" "${off[*]}"; do
        # shellcheck disable=SC2086
        if ! "$clang" -x cl -cl-std="$std" -target spir64-unknown-unknown -Xclang -finclude-default-header \
             -fsyntax-only -cl-single-precision-constant -Werror -Wall -Wno-unused-function -Wno-unused-variable \
             -DHT_FEATURE_LOBE_TT=$1 -DHT_FEATURE_LOBE_TRT=$2 $rest "${extra[@]}" "${render_programs[@]}"; then
            echo "FAILED: the render programs with LOBE_TT=$1 LOBE_TRT=$2 $rest ($std)"
            status=1
        fi
    done
done
# Geometry paged over several buffers (kernels/geometry/pages.h), with the AOV records and the path rays' grid: the render and tracer programs
# unpaged, with 3 pages of 4 KiB and with the maximum of 8, meshes on so every paged array is indexed.
for pages in 1 3 8; do
    for f in trace.cl shade.cl intersect_shadow_afs.cl intersect.cl; do
        if ! "$clang" -x cl -cl-std="$std" -target spir64-unknown-unknown -Xclang -finclude-default-header \
             -fsyntax-only -cl-single-precision-constant -Werror -Wall -Wno-unused-function -Wno-unused-variable \
             -DHT_FEATURE_MESHES=1 -DHT_FEATURE_INDIRECT_AFS=1 -DHT_FEATURE_AOVS=1 -DHT_FEATURE_PATH_GRID=1 -DHT_GEOMETRY_PAGES=$pages -DHT_GEOMETRY_PAGE_LOG2=12 \
             "${extra[@]}" "$root/kernels/stages/$f"; then
            echo "FAILED: kernels/stages/$f with $pages geometry pages ($std)"
            status=1
        fi
    done
done
# The estimator's options (host/render/features.cpp estimator_build_options, kernels/features.h):
# their code is compiled only when the command line asks for it, so compile it here with every one
# on, once with the scene features on and once with them off.
estimator=(-DHT_CLAMP_INDIRECT=3.0f -DHT_REGULARIZE_WIDTH=0.1f -DHT_LIGHT_THRESHOLD=0.1f -DHT_SPAWN_PBRT=1
           -DHT_SAMPLER_SOBOL=1 -DHT_LIGHT_PICK_IMPORTANCE=1 -DHT_LIGHT_GUIDE=0.2f -DHT_LIGHT_VERTICES=1)
for rest in "" "${off[*]}"; do
    # shellcheck disable=SC2086
    if ! "$clang" -x cl -cl-std="$std" -target spir64-unknown-unknown -Xclang -finclude-default-header \
         -fsyntax-only -cl-single-precision-constant -Werror -Wall -Wno-unused-function -Wno-unused-variable \
         "${estimator[@]}" $rest "${extra[@]}" "${render_programs[@]}"; then
        echo "FAILED: the render programs with every estimator option on${rest:+ and the scene features off} ($std)"
        status=1
    fi
done
[ $status = 0 ] && echo "all kernels compile as strict $std for spir64"
exit $status
