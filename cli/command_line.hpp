#pragma once
// What every subcommand does with its command line before its own work.

#include <optional>
#include <string>

namespace CLI {
class App;
}

// The first line of `s`, trailing blanks cut: error messages stay one line.
std::string one_line(std::string s);

// Parses argv into `app`. nullopt: go on. Otherwise the exit status to
// return: 0 after printing --help on stdout, 2 after printing
// "<who>: <error>[ (see <hint>)]" on stderr.
std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv, const std::string& who,
                                      const std::string& hint = "");

// "N" (N x N) or "WxH", each in [lo, hi]; throws ddt::Error naming `option`.
void parse_width_height(const std::string& text, const std::string& option, int lo, int hi, int& width,
                        int& height);

// "X" or "A/B" (a frame-rate ratio, e.g. 60/24 or 30000/1001), in (lo, hi];
// throws ddt::Error naming `option`.
double parse_ratio(const std::string& text, const std::string& option, double lo, double hi);
// A frame rate `rate` times `factor` (both as parse_ratio reads them) as
// FFmpeg takes it, an exact ratio where both are ("24000/1001" x "5/2" is
// "12000/1001"; "24" x "2.5" is "60").
std::string rate_text(const std::string& rate, const std::string& factor);
