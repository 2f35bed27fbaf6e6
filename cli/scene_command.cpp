// `ddtscale scene NAME out.png --size WxH`: render an analytic test scene
// (synthetic_scenes.hpp), box-filtered, to any image format. Used to make
// the synthetic reference inputs in images/ and handy for trying upscalers
// against a known high-resolution answer.

#include "command_line.hpp"
#include "commands.hpp"

#include "util/error.hpp"
#include "io/image_io.hpp"
#include "eval/synthetic_scenes.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>

int run_scene_command(int argc, char** argv) {
  std::string name, output, size = "64x64";
  bool list = false;
  CLI::App app{"Render an analytic test scene, box-filtered over each pixel.", "ddtscale scene"};
  app.add_option("name", name, "scene name (see --list)");
  app.add_option("output", output, "output image; format from the extension (EXR keeps float)");
  app.add_option("--size", size, "width x height in pixels")->capture_default_str();
  app.add_flag("--list", list, "list the scenes and exit");
  if (const auto status = parse_command_line(app, argc, argv, "ddtscale scene", "ddtscale scene --help"))
    return *status;
  try {
    if (list) {
      for (const ddt::Scene& s : ddt::standard_scenes()) std::cout << s.name << "\t" << s.description << "\n";
      return 0;
    }
    if (name.empty() || output.empty()) throw ddt::Error("give a scene name and an output file (see --list)");
    int w = 0, h = 0;
    char extra = 0;
    if (std::sscanf(size.c_str(), "%dx%d%c", &w, &h, &extra) != 2 || w < 1 || h < 1 || w > 16384 || h > 16384)
      throw ddt::Error("--size wants WxH between 1x1 and 16384x16384, got '" + size + "'");
    const ddt::Scene& scene = ddt::find_scene(name);
    ddt::check_output_path(output, "");
    ddt::write_image(output, ddt::render_scene(scene, w, h), ddt::SampleFormat::uint8);
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "ddtscale scene: " << e.what() << "\n";
    return 1;
  }
}
