// Mathematical constants of the host side, in double precision.  The kernels have their own in
// kernels/compat.h (HT_PI in the kernels' `real`); host code that evaluates kernel headers may
// use those, everything else uses these.
#pragma once

namespace ht {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadiansPerDegree = kPi / 180.0;

}  // namespace ht
