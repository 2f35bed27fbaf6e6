#pragma once
// Greyscale pictures of volumes for quick comparison: the three middle
// slices and maximum-intensity projections (the views of the paper's
// figures 9 and 10 that need no renderer), methods side by side.
//
// Conventions: a view of the x-y plane has x to the right and y down
// (the volume's storage order); x-z has x right, z down; y-z has y right,
// z down. The middle slice of an axis of size n is index n / 2.
// Grey levels map [lo, hi] linearly to [0, 1], clamped.

#include "image.hpp"
#include "volume.hpp"

#include <string>
#include <vector>

namespace ddt {

enum class VolumeView { slice_xy, slice_xz, slice_yz, mip_z };
const char* view_name(VolumeView view);  // "middle x-y slice", ...

// One view of `v`, 1 channel, values as stored (not mapped).
Image volume_view(const Volume& v, VolumeView view);

// A grid of views: one column per volume (in the given order), one row per
// view, 4-pixel dark gaps between cells, each cell mapped [lo, hi] -> [0, 1].
// All volumes must have the same size.
Image compare_views(const std::vector<const Volume*>& volumes, const std::vector<VolumeView>& views, double lo,
                    double hi);

// The minimum and maximum sample (for the grey mapping).
void value_range(const Volume& v, double& lo, double& hi);

}  // namespace ddt
