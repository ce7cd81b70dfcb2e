# Shared set-up for tools/demo and tools/test: Debian packages, configure, build.
# Sourced, not run.  Respects BUILD_DIR (default build) and BUILD_TYPE (default Release).

HT_PACKAGES=(build-essential cmake pkg-config git pocl-opencl-icd ocl-icd-opencl-dev opencl-clhpp-headers
             clinfo libopenimageio-dev libglm-dev libtinygltf-dev libtinyobjloader-dev zlib1g-dev nlohmann-json3-dev libgtest-dev
             libgmock-dev libbenchmark-dev clang libclang-rt-14-dev fonts-dejavu-core
             libopenmpi-dev openmpi-bin)

ht_missing_packages() {
    local missing=()
    for p in "${HT_PACKAGES[@]}"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
    done
    echo "${missing[@]:-}"
}

ht_install_packages() {
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
