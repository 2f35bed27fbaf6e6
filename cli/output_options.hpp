#pragma once
// The output's encoding on the command line (io/encode_options.hpp):
//   --compression TEXT   PNG LEVEL[:FILTER], EXR/TIFF method names
//   --quality N          JPEG quality 1..100
//   --half               EXR half floats
//   --no-stream          hold the whole output and write it at the end
//                        (the streamed file is the same, bit for bit)

#include "io/encode_options.hpp"

namespace CLI {
class App;
}

struct OutputOptions {
  ddt::EncodeOptions encode;
  bool no_stream = false;
};

// Adds the options above to `app` (--no-stream only when `streamed`: the
// image command's).
void add_output_options(CLI::App& app, OutputOptions& output, bool streamed = true);
