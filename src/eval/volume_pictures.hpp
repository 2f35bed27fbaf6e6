#pragma once
// Greyscale pictures of volumes for quick comparison: the three middle
// slices and maximum-intensity projections (the views of the paper's
// figures 9 and 10 that need no renderer), methods side by side.
//
// Conventions: a view of the x-y plane has x to the right and y down
// (the volume's storage order); x-z has x right, z down; y-z has y right,
// z down. The middle slice of an axis of size n is index n / 2.
// Grey levels map [lo, hi] linearly to [0, 1], clamped.

#include "util/image.hpp"
#include "volume/volume.hpp"

#include <array>
#include <map>
#include <string>
#include <vector>

namespace ddt {

enum class VolumeView { slice_xy, slice_xz, slice_yz, mip_z, isosurface };

// A shaded isosurface (the view of the paper's figures), drawn by a small
// ray caster written here, not an established renderer: orthographic rays
// from the direction (azimuth about z from +x, elevation above the x-y
// plane), the volume read as the trilinear interpolant of its samples
// (voxel convention of volume.hpp, clamped at the border), the first
// crossing of `level` found by marching in steps of step voxels and
// refined by bisection, Lambert shading with a headlight from the
// normalized gradient (central differences). Good enough to see staircase
// artifacts; no shadows, no transparency.
struct IsoView {
  double level = 0.5;
  double azimuth = 35;    // degrees
  double elevation = 25;  // degrees
  double step = 0.25;     // voxels per marching step
  double zoom = 1;        // 1: the picture spans the volume's bounding sphere
  int size = 0;           // picture side in compare_views (0: max(nx, ny, nz))
};
// The trilinear interpolant of step `step` of v (channel 0) at point p in
// voxel units (sample i at i + 0.5, indices clamped), and the gradient the
// isosurface picture shades with there: its central differences half a
// voxel either side along each axis (unnormalized). isosurface_error
// scores the same normal.
double trilinear_at(const Volume& v, const std::array<double, 3>& p, int step = 0);
std::array<double, 3> shading_gradient(const Volume& v, const std::array<double, 3>& p, int step = 0);

// size x size grey picture in 0..1 (0 where a ray misses the surface);
// the square spans the volume's bounding sphere divided by view.zoom.
// Parallel over rows.
Image isosurface_view(const Volume& v, const IsoView& view, int size);

// One view of `v`, 1 channel, values as stored (not mapped); isosurface
// views are shaded 0..1 at iso.size (default max(nx, ny, nz)) pixels square.
Image volume_view(const Volume& v, VolumeView view, const IsoView& iso = {});

// A grid of views: one column per volume (in the given order), one row per
// view, 4-pixel dark gaps between cells, each cell mapped [lo, hi] -> [0, 1]
// (isosurface cells are already shaded 0..1). All volumes must have the
// same size.
Image compare_views(const std::vector<const Volume*>& volumes, const std::vector<VolumeView>& views, double lo,
                    double hi, const IsoView& iso = {});

// Volume series (4D): the x-t plane at the middle y and z (x right, t
// down), one channel, values as stored.
Image series_xt_view(const Volume& v);

// compare_views of time step `step` of each series (rows `views`), then a
// row of their x-t planes (series_xt_view), same columns and grey mapping.
Image compare_series_views(const std::vector<const Volume*>& series, int step, const std::vector<VolumeView>& views,
                           double lo, double hi, const IsoView& iso = {});

// The minimum and maximum sample (for the grey mapping).
void value_range(const Volume& v, double& lo, double& hi);

// The columns of an experiment's pictures: `reference`, then the volume of
// each picture method in `results`; throws ddt::Error naming a method that
// was not run.
std::vector<const Volume*> picture_columns(const Volume& reference, const std::map<std::string, Volume>& results,
                                           const std::vector<std::string>& methods);

}  // namespace ddt
