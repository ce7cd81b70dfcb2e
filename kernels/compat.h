/* The only file that knows OpenCL C from C++.
 *
 * Everything under kernels/ that is not a stage kernel (*.cl) is a portable header: it compiles as
 * OpenCL C 1.2 (where `real` is float) and as C++17 on the host (where `real` is double), so the
 * host tests run the very lines the kernels run, in double precision.  Shared struct layouts
 * (types.h) use explicit float/uint fields only, never `real`, so they are identical on both sides.
 *
 * Vocabulary available to portable code:
 *   real, real3, uint, ulong          scalar / 3-vector of the working precision
 *   make_real3(x,y,z), dot, cross, length, normalize, r3_x/y/z accessors via .x .y .z
 *   HT_FN                              function qualifier for helpers in headers
 *   HT_FIBER_FN                        the same for kernels/fiber/ (force-inlined where HT_FIBER_INLINE is defined)
 *   HT_NOINLINE                        keeps a helper a called function in the kernels (a hint; the host ignores it)
 *   HT_GLOBAL, HT_CONST_GLOBAL         address-space qualifiers for buffer pointers
 *   HT_PREFETCH(p)                     a hint to start loading *p's cache line (nothing where unsupported)
 *   ht_select(c, a, b)                 compare-select min/max friendly form (PoCL: faster than fmin)
 *   ht_as_uint / ht_as_float           bit casts
 *   HT_PI, HT_INV_PI, HT_REAL_MAX
 *   HT_R(x)                            a literal or value in the working precision (namespaced:
 *                                      a one-letter macro would clash with templates in host code)
 */
#ifndef HT_COMPAT_H
#define HT_COMPAT_H

#if defined(__OPENCL_C_VERSION__) || defined(__OPENCL_VERSION__)
/* ------------------------------------------------------------------ OpenCL C 1.2 */
#define HT_OPENCL 1
typedef float real;
typedef float3 real3;
#define HT_FN static inline
/* The fibre models' functions (kernels/fiber/).  A program that defines HT_FIBER_INLINE before its
 * first include gets them force-inlined: the shade stage does (kernels/stages/shade.cl says what it
 * buys and costs); traversal is the opposite case (docs/POCL.md section 1). */
#ifdef HT_FIBER_INLINE
#define HT_FIBER_FN static inline __attribute__((always_inline))
#else
#define HT_FIBER_FN HT_FN
#endif
/* A helper kept out of its callers' code: the traversal loops run faster with the leaf test
 * called than inlined into them (docs/POCL.md section 1).  A clang/GCC attribute, which every
 * LLVM-based OpenCL compiler takes; elsewhere the call is inlined as before. */
#if defined(__clang__) || defined(__GNUC__)
#define HT_NOINLINE __attribute__((noinline))
#else
#define HT_NOINLINE
#endif
#define HT_GLOBAL __global
#define HT_CONST_GLOBAL __global const
#define HT_PRIVATE __private
#define make_real3(x, y, z) ((float3)((x), (y), (z)))
#define ht_as_uint(f) as_uint(f)
#define ht_as_float(u) as_float(u)
#define HT_REAL_MAX 3.0e38f
#define HT_REAL_EPS 1.1920929e-7f
#define HT_R(x) ((float)(x))

#else
/* ------------------------------------------------------------------ C++ host */
#define HT_HOST 1
#include <cmath>
#include <cstdint>
#include <cstring>
#include <algorithm>

#ifndef HT_HOST_REAL
#define HT_HOST_REAL double
#endif
typedef HT_HOST_REAL real;
typedef std::uint32_t uint;
typedef std::uint64_t ulong;

#define HT_FN static inline
#define HT_FIBER_FN HT_FN
#define HT_NOINLINE
#define HT_GLOBAL
#define HT_CONST_GLOBAL const
#define HT_PRIVATE
#define HT_REAL_MAX 3.0e38
#define HT_REAL_EPS 1.1920929e-7
#define HT_R(x) ((real)(x))

using std::sqrt; using std::exp; using std::log; using std::fabs; using std::sin; using std::cos;
using std::asin; using std::acos; using std::atan2; using std::floor; using std::pow; using std::tan;
using std::log1p; using std::expm1; using std::cosh; using std::sinh; using std::isfinite;

template <typename T> struct ht_vec3 {
    T x, y, z;
};
typedef ht_vec3<real> real3;

HT_FN real3 make_real3(real x, real y, real z) { real3 v = {x, y, z}; return v; }
HT_FN real3 operator+(real3 a, real3 b) { return make_real3(a.x + b.x, a.y + b.y, a.z + b.z); }
HT_FN real3 operator-(real3 a, real3 b) { return make_real3(a.x - b.x, a.y - b.y, a.z - b.z); }
HT_FN real3 operator-(real3 a) { return make_real3(-a.x, -a.y, -a.z); }
HT_FN real3 operator*(real3 a, real3 b) { return make_real3(a.x * b.x, a.y * b.y, a.z * b.z); }
HT_FN real3 operator*(real3 a, real s) { return make_real3(a.x * s, a.y * s, a.z * s); }
HT_FN real3 operator*(real s, real3 a) { return make_real3(a.x * s, a.y * s, a.z * s); }
HT_FN real3 operator/(real3 a, real s) { return make_real3(a.x / s, a.y / s, a.z / s); }
HT_FN real3 operator/(real3 a, real3 b) { return make_real3(a.x / b.x, a.y / b.y, a.z / b.z); }
HT_FN real3& operator+=(real3& a, real3 b) { a = a + b; return a; }
HT_FN real3& operator-=(real3& a, real3 b) { a = a - b; return a; }
HT_FN real3& operator*=(real3& a, real3 b) { a = a * b; return a; }
HT_FN real3& operator*=(real3& a, real s) { a = a * s; return a; }
HT_FN real dot(real3 a, real3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
HT_FN real3 cross(real3 a, real3 b) {
    return make_real3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
HT_FN real length(real3 a) { return std::sqrt(dot(a, a)); }
HT_FN real3 normalize(real3 a) { return a * (HT_R(1) / length(a)); }
/* <cmath> already declares ::fmin/::fmax(double, double) extern; redefining them static fails. */
using std::fmin; using std::fmax;
HT_FN real clamp(real x, real lo, real hi) { return x < lo ? lo : (x > hi ? hi : x); }
HT_FN real mix(real a, real b, real t) { return a + (b - a) * t; }
HT_FN real native_exp(real x) { return std::exp(x); }
HT_FN real native_sqrt(real x) { return std::sqrt(x); }
HT_FN real native_recip(real x) { return HT_R(1) / x; }
HT_FN real rsqrt(real x) { return HT_R(1) / std::sqrt(x); }
HT_FN real sign(real x) { return x > 0 ? HT_R(1) : (x < 0 ? HT_R(-1) : HT_R(0)); }
HT_FN real3 fabs3(real3 a) { return make_real3(std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)); }
HT_FN uint ht_as_uint(float f) { uint u; std::memcpy(&u, &f, 4); return u; }
HT_FN float ht_as_float(uint u) { float f; std::memcpy(&f, &u, 4); return f; }
HT_FN uint mul_hi(uint a, uint b) { return (uint)(((ulong)a * (ulong)b) >> 32); }
#endif

/* ------------------------------------------------------------------ both */
#define HT_PI HT_R(3.14159265358979323846)
#define HT_TWO_PI HT_R(6.28318530717958647692)
#define HT_INV_PI HT_R(0.31830988618379067154)
#define HT_INV_TWO_PI HT_R(0.15915494309189533577)
#define HT_INV_FOUR_PI HT_R(0.07957747154594766788)

/* A hint that the cache line holding *p will be read soon, which lets a load that may miss start
 * before the code that needs it: clang's and GCC's builtin (OpenCL's own prefetch() compiles to
 * nothing on PoCL: host/bvh/NOTES.md "Tried in session 28"); elsewhere nothing. */
#if defined(__clang__) || defined(__GNUC__)
#define HT_PREFETCH(p) __builtin_prefetch(p)
#else
#define HT_PREFETCH(p) ((void)0)
#endif

#define ht_select(c, a, b) ((c) ? (a) : (b))
HT_FN real ht_min(real a, real b) { return a < b ? a : b; }
HT_FN real ht_max(real a, real b) { return a > b ? a : b; }
HT_FN real ht_clamp(real x, real lo, real hi) { return x < lo ? lo : (x > hi ? hi : x); }
HT_FN real ht_sqr(real x) { return x * x; }
/* sqrt that tolerates tiny negative arguments from rounding (1 - x*x with |x| = 1 + eps). */
HT_FN real ht_safe_sqrt(real x) { return sqrt(ht_max(x, HT_R(0))); }
HT_FN real ht_safe_asin(real x) { return asin(ht_clamp(x, HT_R(-1), HT_R(1))); }
HT_FN real ht_safe_acos(real x) { return acos(ht_clamp(x, HT_R(-1), HT_R(1))); }

/* Finite test that survives -cl-fast-relaxed-math (which lets the compiler assume no NaN/Inf and
 * fold isfinite() to true): look at the exponent bits instead. */
#ifdef HT_OPENCL
HT_FN int ht_isfinite(float x) { return (as_uint(x) & 0x7f800000u) != 0x7f800000u; }
#else
HT_FN int ht_isfinite(double x) { return std::isfinite(x) ? 1 : 0; }
#endif

#endif /* HT_COMPAT_H */
