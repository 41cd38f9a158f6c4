// Procedural textures (albedo in [0, 1]) for the synthetic scene. Every surface gets a pattern
// with both coarse structure and fine, non-repeating detail so that multi-view correspondences
// are unambiguous.
#pragma once
#include "s4d/synth/ray.h"

namespace s4d::synth {

// Smooth value noise in [0, 1] on an integer lattice, deterministic (no seed: the scene is fixed).
double value_noise(double x, double y);

// Background wall (the plane z = const), coordinates on the wall in metres.
Vec3 wall_albedo(double x, double y);
// Floor (the plane y = const).
Vec3 floor_albedo(double x, double z);
// Sphere, from the unit direction of the hit in the sphere's own (rotating) frame.
Vec3 sphere_albedo(Vec3 local_dir);
// Box face `axis`/`sign` (as in BoxHit), at face coordinates (u, v) in [-1, 1].
Vec3 box_albedo(int axis, int sign, double u, double v);
// Wave sheet at (u, v) in [0, 1]^2 across its rectangle; `front` tells the +z side from the back.
Vec3 sheet_albedo(double u, double v, bool front);

}  // namespace s4d::synth
