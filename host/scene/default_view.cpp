// The view a scene gets when its file says nothing: which way is up, a camera that looks at the
// hair from the side, and a light rig.  docs/CLI.md "Scenes" documents the same rules for users.
//
// Up axis (detect_up_axis).  Hair grows from its root (a strand's first point) to its tip (the
// last), and on a head or a lock gravity pulls tips below roots; so, in order:
//   1. u = mean over strands of the unit vector tip -> root.  The axis a with the largest |u_a|
//      is up, signed like u_a, when |u_a| >= 0.3 (a clear common direction);
//   2. otherwise (short, curly or radial hair), the roots' centroid relative to the centre of the
//      bounds, per axis in units of that axis' half extent: the largest |.| >= 0.25 names the
//      axis and its sign (roots sit on top of the hair);
//   3. otherwise +y, the glTF convention.
// Cem Yuksel's models (z-up) come out +z by rule 1.
//
// Camera.  The front of a model is where its hair does not fall: tips hang behind the roots, so
// the horizontal part (across the up axis) of root centroid minus tip centroid, snapped to the
// nearest axis, points to the front when it is longer than 5 % of the hair's extent (Yuksel's
// straight.hair: +y).  Otherwise (a lock hanging straight down) a convention: -y for z-up
// (Blender, 3ds Max), +z for y-up (glTF) and for x-up.  The camera looks from the front turned
// 45 degrees about the up axis and raised 10 degrees (a 3/4 front view: the hair's side and its
// parting both show; on straight.hair it shows more lit hair than 35 degrees and 15) at the
// centre of the hair's silhouette, from the nearest distance at which every point plus its
// radius lies inside the field of view (30 degrees unless stated) with a 2 % margin on a square
// image.  A wider image only adds
// margin at the sides.
//
// Light rig (directional, so a model looks the same at any scale; irradiance at the hair, angles
// from the camera's direction about the image's up, then above the horizon): key 1.0 from 30
// degrees right and 35 up; rim 1.5 from straight behind and 40 up (light transmitted through the
// hair, which makes light hair glow at its silhouette); fill 0.5 from 50 degrees left and 10 up,
// so the side away from the key is not black.  The rig is placed relative to the camera, so it
// follows --look-from.
#include <algorithm>
#include <cmath>

#include "scene/scene.h"
#include "scene/scene_error.h"

namespace ht {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDefaultFovDeg = 30.0;
constexpr double kTurnDeg = 45.0, kRaiseDeg = 10.0, kMargin = 1.02;
constexpr double kClearDirection = 0.3, kClearRootOffset = 0.25;
// Light rig: azimuth from the camera towards its right, elevation, irradiance.
constexpr double kKey[3] = {30, 35, 1.0}, kRim[3] = {180, 40, 1.5}, kFill[3] = {-50, 10, 0.5};

struct V3 {
    double x, y, z;
};
V3 v3(const Vec3f& v) { return {v[0], v[1], v[2]}; }
Vec3f f3(const V3& v) { return {float(v.x), float(v.y), float(v.z)}; }
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator*(double s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double length(V3 a) { return std::sqrt(dot(a, a)); }
V3 normalize(V3 a) { return (1.0 / length(a)) * a; }
double component(V3 a, int axis) { return axis == 0 ? a.x : axis == 1 ? a.y : a.z; }
V3 unit_axis(int axis, double sign) {
    V3 v{0, 0, 0};
    (axis == 0 ? v.x : axis == 1 ? v.y : v.z) = sign < 0 ? -1.0 : 1.0;
    return v;
}
int largest_component(V3 a) {
    const double ax = std::abs(a.x), ay = std::abs(a.y), az = std::abs(a.z);
    return ax >= ay && ax >= az ? 0 : ay >= az ? 1 : 2;
}

// The conventional front of a model with this up axis (see the top of the file).
V3 conventional_front(V3 up) { return largest_component(up) == 2 ? V3{0, -1, 0} : V3{0, 0, 1}; }

// The model's front: away from where the tips hang (see the top of the file).
V3 front_of(const Strands& st, V3 up, double extent) {
    V3 roots{0, 0, 0}, tips{0, 0, 0};
    const size_t n = st.strand_count();
    for (size_t s = 0; s < n; ++s) {
        roots = roots + v3(st.points[st.first_point[s]]);
        tips = tips + v3(st.points[st.first_point[s + 1] - 1]);
    }
    if (n == 0) return conventional_front(up);
    const V3 d = (1.0 / double(n)) * (roots - tips);
    V3 across = d - dot(d, up) * up;
    if (!(length(across) > 0.05 * extent)) return conventional_front(up);
    const int axis = largest_component(across);
    return unit_axis(axis, component(across, axis));
}

// Camera basis: right and up of the image for a camera at `eye` looking at `target`.
struct Basis {
    V3 back, right, up;  // back: from the target towards the eye
};
Basis basis(V3 eye, V3 target, V3 up) {
    Basis b;
    b.back = normalize(eye - target);
    b.right = normalize(cross(up, b.back));
    b.up = cross(b.back, b.right);
    return b;
}

// The automatic camera: a 3/4 front view fitted to the hair (see the top of the file).
Camera framed_camera(const Scene& s, V3 up, double fov_deg) {
    const Strands& st = s.strands;
    const Bounds bounds = scene_bounds(s);
    V3 centre = 0.5 * (v3(bounds.lo) + v3(bounds.hi));
    const double extent = length(v3(bounds.hi) - v3(bounds.lo));
    const V3 front = front_of(st, up, extent), side = cross(up, front);
    const double turn = kTurnDeg * kPi / 180.0, raise = kRaiseDeg * kPi / 180.0;
    const V3 back = std::cos(raise) * (std::cos(turn) * front + std::sin(turn) * side) + std::sin(raise) * up;
    const Basis b = basis(centre + back, centre, up);

    // Centre the silhouette: the middle of the points' extent across the image plane.
    double lo_x = 0, hi_x = 0, lo_y = 0, hi_y = 0;
    for (size_t i = 0; i < st.points.size(); ++i) {
        const V3 q = v3(st.points[i]) - centre;
        const double r = st.radius[i], x = dot(q, b.right), y = dot(q, b.up);
        if (i == 0) lo_x = hi_x = x, lo_y = hi_y = y;
        lo_x = std::min(lo_x, x - r), hi_x = std::max(hi_x, x + r);
        lo_y = std::min(lo_y, y - r), hi_y = std::max(hi_y, y + r);
    }
    const V3 target = centre + 0.5 * (lo_x + hi_x) * b.right + 0.5 * (lo_y + hi_y) * b.up;

    // The nearest distance along `back` that keeps every point inside the view cone.
    const double tan_half = std::tan(fov_deg * kPi / 360.0);
    double distance = 1e-6;
    for (size_t i = 0; i < st.points.size(); ++i) {
        const V3 q = v3(st.points[i]) - target;
        const double r = st.radius[i], depth = dot(q, b.back);
        const double across = std::max(std::abs(dot(q, b.right)), std::abs(dot(q, b.up))) + r;
        distance = std::max({distance, depth + kMargin * across / tan_half, depth + 2 * r});
    }
    Camera cam;
    cam.yfov_deg = float(fov_deg);
    cam.target = f3(target);
    cam.eye = f3(target + distance * back);
    cam.up = f3(up);
    return cam;
}

Light directional(V3 towards_light, double irradiance) {
    Light l;
    l.type = LightType::Directional;
    l.direction = f3(-1.0 * normalize(towards_light));
    l.intensity = float(irradiance);
    return l;
}

}  // namespace

Vec3f detect_up_axis(const Strands& st) {
    V3 mean_dir{0, 0, 0}, root_sum{0, 0, 0};
    size_t counted = 0;
    for (size_t s = 0; s < st.strand_count(); ++s) {
        const V3 root = v3(st.points[st.first_point[s]]), tip = v3(st.points[st.first_point[s + 1] - 1]);
        root_sum = root_sum + root;
        const double len = length(root - tip);
        if (!(len > 0)) continue;
        mean_dir = mean_dir + (1.0 / len) * (root - tip);
        ++counted;
    }
    if (counted > 0) {
        mean_dir = (1.0 / double(counted)) * mean_dir;
        const int a = largest_component(mean_dir);
        if (std::abs(component(mean_dir, a)) >= kClearDirection) return f3(unit_axis(a, component(mean_dir, a)));
    }
    if (st.strand_count() > 0) {
        Scene only_hair;
        only_hair.strands = st;
        const Bounds b = scene_bounds(only_hair);
        const V3 roots = (1.0 / double(st.strand_count())) * root_sum;
        V3 offset{0, 0, 0};
        for (int a = 0; a < 3; ++a) {
            const double half = 0.5 * (b.hi[a] - b.lo[a]);
            const double o = half > 0 ? (component(roots, a) - 0.5 * (b.lo[a] + b.hi[a])) / half : 0.0;
            (a == 0 ? offset.x : a == 1 ? offset.y : offset.z) = o;
        }
        const int a = largest_component(offset);
        if (std::abs(component(offset, a)) >= kClearRootOffset) return f3(unit_axis(a, component(offset, a)));
    }
    return {0, 1, 0};
}

void ensure_camera_and_light(Scene& s, const ViewOptions& view) {
    const bool has_hair = !s.strands.points.empty();
    const V3 model_up = view.up_axis ? v3(*view.up_axis) : has_hair ? v3(detect_up_axis(s.strands)) : V3{0, 1, 0};
    if (!s.has_camera) {
        if (has_hair) {
            s.camera = framed_camera(s, model_up, view.yfov_deg.value_or(float(kDefaultFovDeg)));
        } else {
            s.camera = Camera{};
            s.camera.up = f3(model_up);
        }
        s.has_camera = true;
    }
    Camera& cam = s.camera;
    if (view.look_from) cam.eye = *view.look_from;
    if (view.look_at) cam.target = *view.look_at;
    if (view.yfov_deg) cam.yfov_deg = *view.yfov_deg;
    if (view.up) cam.up = *view.up;
    const V3 eye = v3(cam.eye), target = v3(cam.target);
    if (!(length(eye - target) > 0))
        scene_fail(s.source, "the camera's position and target are the same point (", cam.eye[0], ", ",
                   cam.eye[1], ", ", cam.eye[2], ")");
    if (!(length(cross(normalize(eye - target), v3(cam.up))) > 1e-6)) {
        if (view.up) scene_fail(s.source, "the camera's up vector is parallel to its view direction");
        // Looking straight along the model's up axis (a view from above): the front is up in the image.
        cam.up = f3(conventional_front(model_up));
    }

    if (s.lights.empty() && !s.environment.enabled()) {
        const Basis b = basis(eye, target, v3(cam.up));
        auto from = [&b](double azimuth_deg, double elevation_deg) {  // azimuth 0: the camera, 90: its right
            const double az = azimuth_deg * kPi / 180.0, el = elevation_deg * kPi / 180.0;
            return std::cos(el) * (std::cos(az) * b.back + std::sin(az) * b.right) + std::sin(el) * b.up;
        };
        s.lights.push_back(directional(from(kKey[0], kKey[1]), kKey[2]));
        s.lights.push_back(directional(from(kRim[0], kRim[1]), kRim[2]));
        s.lights.push_back(directional(from(kFill[0], kFill[1]), kFill[2]));
    }
}

}  // namespace ht
