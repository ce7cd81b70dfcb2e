#!/bin/sh
# Strong-scaling measurements for docs/SCALING.md: one render split over 1 and 2 workers
# (PoCL threads, OpenCL devices, MPI ranks).  Usage: tools/measure_scaling.sh [BUILD_DIR]
# Prints "config seconds" lines (best of two wall-clock runs; on a shared machine also compare
# CPU times with /usr/bin/time, as docs/SCALING.md does).
set -eu
B=${1:-build}/hairtrace
SCENE=${SCENE:-scenes/default.gltf}
ARGS="render $SCENE --width ${W:-256} --height ${H:-256} --spp ${SPP:-16} --chunk ${CHUNK:-2} --quiet"
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
best() {  # best wall time of two runs of "$@"
    b=""
    for _ in 1 2; do
        t0=$(date +%s.%N); "$@" >/dev/null 2>&1; t1=$(date +%s.%N)
        t=$(echo "$t1 - $t0" | bc)
        if [ -z "$b" ] || [ "$(echo "$t < $b" | bc)" = 1 ]; then b=$t; fi
    done
    echo "$b"
}
echo "1proc_1thread $(POCL_MAX_PTHREAD_COUNT=1 best $B $ARGS -o $OUT/a.exr)"
echo "1proc_2threads $(best $B $ARGS -o $OUT/b.exr)"
echo "1dev_basic $(POCL_DEVICES=basic best $B $ARGS -o $OUT/c.exr)"
echo "2dev_basic $(POCL_DEVICES='basic basic' best $B $ARGS --device all -o $OUT/d.exr)"
if command -v mpirun >/dev/null; then
    MPI="mpirun --oversubscribe --allow-run-as-root -x POCL_MAX_PTHREAD_COUNT=1"
    echo "mpi_np1_1thread $(POCL_MAX_PTHREAD_COUNT=1 best $MPI -np 1 $B $ARGS -o $OUT/e.exr)"
    echo "mpi_np2_1thread $(POCL_MAX_PTHREAD_COUNT=1 best $MPI -np 2 $B $ARGS -o $OUT/f.exr)"
fi
echo "startup_only $(best $B render $SCENE --width 8 --height 8 --spp 1 --quiet -o $OUT/g.exr)"
