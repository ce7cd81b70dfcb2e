# Shared set-up for tools/demo and tools/test: Debian packages, configure, build.
# Sourced, not run.  Respects BUILD_DIR (default build) and BUILD_TYPE (default Release).

# What building and rendering need (tools/demo): compiler, CMake, an OpenCL runtime (PoCL) and
# headers, and the libraries CMakeLists.txt requires.
HT_RUNTIME_PACKAGES=(build-essential cmake pkg-config pocl-opencl-icd ocl-icd-opencl-dev opencl-clhpp-headers
                     libopenimageio-dev libglm-dev libtinygltf-dev libtinyobjloader-dev zlib1g-dev nlohmann-json3-dev)
# Everything the tests use besides (tools/test, CI): GoogleTest and Benchmark, clang for the
# kernel portability check and the sanitizers, the converge plot's font, Open MPI for the MPI
# equality tests, clinfo and git, Python for tools/pbrt-compare's check against pbrt-v4's images.
HT_TEST_PACKAGES=(git clinfo libgtest-dev libgmock-dev libbenchmark-dev clang libclang-rt-14-dev fonts-dejavu-core
                  libopenmpi-dev openmpi-bin python3)
HT_PACKAGES=("${HT_RUNTIME_PACKAGES[@]}" "${HT_TEST_PACKAGES[@]}")

ht_missing_packages() {
    local missing=()
    for p in "${HT_PACKAGES[@]}"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
    done
    echo "${missing[@]:-}"
}

# ht_install_packages [runtime]: every package, or with `runtime` only HT_RUNTIME_PACKAGES.
ht_install_packages() {
    if [ "${1:-}" = runtime ]; then HT_PACKAGES=("${HT_RUNTIME_PACKAGES[@]}"); fi
    local missing
    missing=$(ht_missing_packages)
    [ -z "$missing" ] && return 0
    if [ "$(id -u)" = 0 ]; then
        echo "installing: $missing" >&2
        export DEBIAN_FRONTEND=noninteractive
        apt-get update -qq
        # shellcheck disable=SC2086
        apt-get install -y -qq --no-install-recommends $missing >/dev/null
    else
        echo "missing Debian packages; install them with:" >&2
        echo "  sudo apt-get install -y $missing" >&2
        return 1
    fi
}

ht_build() {
    local build_dir=${BUILD_DIR:-build}
    local build_type=${BUILD_TYPE:-Release}
    cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE="$build_type" "$@" >/dev/null
    cmake --build "$build_dir" -j"$(nproc)"
}
