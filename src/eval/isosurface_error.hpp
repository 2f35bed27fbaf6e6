#pragma once
// How far a reconstructed isosurface lies from the true one: the number
// behind "cleaner by the isosurface picture". Terraces, ripples, folds and
// ghosts all move the level crossings off the true surface; a blur that
// keeps the surface in place does not.
//
// The crossings: along every grid line of every axis (x, y and z) of each
// scored time step, each pair of neighbouring samples on either side of
// the level (one below, the other at or above it) gives one crossing,
// placed by linear interpolation between the two. Each crossing's distance
// to the true surface comes from the field's signed distance, in units of
// the volume's voxel along x (the unit cube over nx voxels: 1/nx; the
// experiments' volumes are cubes). The true
// crossings are counted the same way from the signed distance's sign at
// the samples, so a method that loses or adds surface shows in the count.
//
// Sample positions: voxel centres in space, ((i + 0.5) / n), and instants
// in time, step l at l / (nt - 1) (0 for a single step): the conventions of
// volume_fields.hpp. Values are above the level inside the surface, where
// the distance is negative.

#include "volume/volume.hpp"

#include <functional>

namespace ddt {

// Signed distance from (x, y, z) to the true isosurface at time t, unit
// cube coordinates, negative inside.
using SurfaceDistance = std::function<double(double x, double y, double z, double t)>;

struct IsosurfaceError {
  long long crossings = 0;       // level crossings found in the volume
  long long true_crossings = 0;  // sign changes of the distance between the same sample pairs
  double rms = 0;                // root mean square distance of the crossings, output voxels
  double mean = 0;
  double p99 = 0;  // 99th percentile
  double max = 0;
  // The shading's error: at each crossing, the angle in degrees between
  // the normal the isosurface picture shades with (volume_pictures.cpp:
  // central differences half a voxel either side of the trilinear
  // interpolant, outward where values fall) and the true surface's normal
  // (the distance's gradient). Terraces, ripples and folds tilt it even
  // where the surface's place is right; a missing gradient counts 90.
  double normal_rms = 0;
  double normal_p99 = 0;
};

// Scores channel 0 of v over the time steps for which score_step(l) is
// true (all when null). Errors: throws ddt::Error for an empty volume or no
// distance function.
IsosurfaceError isosurface_error(const Volume& v, double level, const SurfaceDistance& distance,
                                 const std::function<bool(int step)>& score_step = nullptr);

}  // namespace ddt
