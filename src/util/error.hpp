#pragma once
// ddt::Error lives in the public header (the library's users catch it).
#include "ddtscale/error.hpp"
