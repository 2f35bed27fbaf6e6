#include "eval/classic_resize.hpp"

// Apart from classic_resize.cpp, so the command line's parser names them
// without linking OpenImageIO (cli/front_main.cpp).
namespace ddt {

std::vector<std::string> classic_methods() { return {"nearest", "bilinear", "bicubic", "lanczos"}; }

}  // namespace ddt
