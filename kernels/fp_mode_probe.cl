/* Multiplies pairs of floats as the kernels' own arithmetic does, so that a test can see whether
 * a program's build options flush denormal results to zero (tests/kernel/fp_mode_test.cpp). */
__kernel void fp_mode_probe(__global const float* a, __global const float* b, __global float* out, uint n) {
    const uint i = get_global_id(0);
    if (i < n) out[i] = a[i] * b[i];
}
