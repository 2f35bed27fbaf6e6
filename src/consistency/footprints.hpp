#pragma once
// ddt::FootprintPixels, ddt::RowBand — which output pixels belong to which
// input pixel, and where a band of rows sits in the whole image.
//
// The consistent reconstruction's last steps (halo_limit.hpp,
// step_edges.hpp) work footprint by footprint: the output pixels whose
// centres lie in one input pixel. A band of rows (a tile, a Dask block)
// holds some input rows and the output rows sampled in them; every
// position is the whole image's, so that a band computes its footprints
// to the same bits as the whole image.

#include <vector>

namespace ddt {

// Footprint x holds columns [first_x[x], first_x[x + 1]), likewise rows.
struct FootprintPixels {
  std::vector<int> first_x, first_y;
};
FootprintPixels footprint_pixels(int width, int height, int out_width, int out_height);

// A band's input image holds rows [src_top, src_top + rows) of an image of
// image_height rows; its output holds rows [out_origin, out_origin +
// out rows) of out_height. Zero heights: the band is the whole image.
struct RowBand {
  int src_top = 0, image_height = 0;
  int out_origin = 0, out_height = 0;
};

}  // namespace ddt
