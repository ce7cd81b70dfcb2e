/* Pinhole camera: pixel (px, py) with a jitter in [0,1)^2 -> world-space primary ray. */
#ifndef HT_CAMERA_H
#define HT_CAMERA_H

#include "types.h"

HT_FN HtRay ht_camera_ray(const HtCamera* cam, uint px, uint py, real jx, real jy) {
    /* NDC in [-1, 1]; py = 0 is the top row */
    real sx = HT_R(2) * (((real)px + jx) / (real)cam->width) - HT_R(1);
    real sy = HT_R(1) - HT_R(2) * (((real)py + jy) / (real)cam->height);
    real3 f = make_real3(cam->forward[0], cam->forward[1], cam->forward[2]);
    real3 r = make_real3(cam->right[0], cam->right[1], cam->right[2]);
    real3 u = make_real3(cam->up[0], cam->up[1], cam->up[2]);
    real3 d = normalize(f + r * sx + u * sy);
    HtRay ray;
    ray.ox = cam->eye[0];
    ray.oy = cam->eye[1];
    ray.oz = cam->eye[2];
    ray.tmin = 0.0f;
    ray.dx = (float)d.x;
    ray.dy = (float)d.y;
    ray.dz = (float)d.z;
    ray.tmax = 1e30f;
    return ray;
}

#endif
