// Golden-image regression: every reference input in images/regression/inputs,
// upscaled x3 with every DDT cost (default cubic render) and with the
// paper's costs under the linear render, must match its golden output in
// images/regression/golden (named <input>__<cost>__<render>__x3.exr).
// Goldens change only through scripts/regenerate_goldens.sh, on purpose.

#include "core/costs.hpp"
#include "io/image_io.hpp"
#include "pipeline/upscale.hpp"

#include <OpenImageIO/imagebufalgo.h>
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <tuple>

using namespace ddt;
namespace fs = std::filesystem;

namespace {
const fs::path regression_dir = fs::path(DDTSCALE_SOURCE_DIR) / "images" / "regression";
// Float goldens of the same computation agree to rounding; allow a little
// for compilers that contract multiply-adds differently.
constexpr double tolerance = 1e-5;
}  // namespace

TEST_CASE("regression: every input and cost matches its golden output") {
  std::vector<fs::path> inputs;
  for (const auto& entry : fs::directory_iterator(regression_dir / "inputs"))
    if (entry.path().extension() == ".png") inputs.push_back(entry.path());
  std::sort(inputs.begin(), inputs.end());
  REQUIRE(inputs.size() >= 5);
  int compared = 0;
  for (const fs::path& input : inputs) {
    const ImageFile file = read_image(input.string());
    // (cost, render, model): every cost under the point model (the goldens
    // named without a model), and the default box model's consistent
    // reconstruction for both renders.
    std::vector<std::tuple<std::string, std::string, std::string>> configs;
    for (const CostFunction& cost : cost_functions()) configs.emplace_back(cost.name, "cubic", "point");
    for (const char* cost : {"sederberg", "variance"}) configs.emplace_back(cost, "linear", "point");
    for (const char* render : {"cubic", "linear"}) configs.emplace_back("sederberg", render, "box");
    for (const auto& [cost, render, model] : configs) {
      const std::string name =
          input.stem().string() + "__" + cost + "__" + render + (model == "point" ? "" : "__" + model) + "__x3";
      CAPTURE(name);
      const fs::path golden_path = regression_dir / "golden" / (name + ".exr");
      // A new cost needs goldens: run scripts/regenerate_goldens.sh and commit them.
      REQUIRE_MESSAGE(fs::exists(golden_path), "missing golden " << golden_path.string()
                                                                 << " (scripts/regenerate_goldens.sh makes it)");
      const ImageFile golden = read_image(golden_path.string());
      UpscaleOptions options;
      options.cost = cost;
      options.render = render_by_name(render);
      options.model = parse_acquisition_model(model);
      options.alpha_channel = file.alpha_channel;
      const Image out = upscale(file.image, 3 * file.image.width, 3 * file.image.height, options);
      REQUIRE(out.width == golden.image.width);
      REQUIRE(out.height == golden.image.height);
      REQUIRE(out.channels == golden.image.channels);
      double largest = 0;
      for (std::size_t i = 0; i < out.pixels.size(); ++i)
        largest = std::max(largest, std::abs(double(out.pixels[i]) - golden.image.pixels[i]));
      if (largest > tolerance) {
        OIIO::ImageBuf diff = OIIO::ImageBufAlgo::absdiff(buf_from_image(out), buf_from_image(golden.image));
        const std::string diff_path = (fs::current_path() / ("regression_diff_" + name + ".exr")).string();
        diff.write(diff_path);
        MESSAGE("largest difference " << largest << "; difference image written to " << diff_path);
      }
      CHECK(largest <= tolerance);
      ++compared;
    }
  }
  MESSAGE("compared " << compared << " outputs with their goldens");
}
