#pragma once
// ddt::read_point_table — scattered samples from a text file: one point per
// line, x, y and one or more values.
//
// Accepted layouts (detected from the first line that is not blank or a
// comment):
//   - delimited text (CSV): fields separated by ',' or, when the line has
//     no comma, by ';'. RFC 4180 quoting ("a, b", "" for a quote inside a
//     quoted field) is handled by libcsv, so text columns with commas may
//     sit beside the numbers. A quoted field may not span lines.
//   - whitespace-separated text: fields separated by runs of spaces or tabs,
//     e.g. the ASCII XYZ grids GIS tools write (`gdal_translate -of XYZ`:
//     "x y z" per cell, with or without an "X Y Z" header).
// Lines whose first non-blank character is '#' are comments; blank lines are
// skipped. A UTF-8 byte order mark and CR-LF line ends are accepted.
// Header: the first line is a header when its first field is not a number.
//
// Columns: by default x is column 1, y column 2 and every further column a
// value (an output channel). `columns` picks them instead, by header name
// (case-insensitive) or 1-based number: {x, y, value, value, ...}; the
// other columns are then ignored and may hold text.
//
// Strict: every line must have as many fields as the first; every selected
// field must be a finite number ('+' sign, exponents allowed; no decimal
// commas). A violation throws ddt::Error with a one-line message naming the
// file and line, e.g. "cannot read 'p.csv', line 7: field 3 'abc' is not a
// number". Numbers are parsed with std::from_chars (locale-independent,
// correctly rounded).
//
// Input no-data: when `input_nodata` is set, a point with any value equal
// to it (or, for NaN, any NaN value) is dropped and counted; x and y must
// still be finite.

#include "image/mesh.hpp"
#include "util/size_limits.hpp"

#include <istream>
#include <optional>
#include <string>
#include <vector>

namespace ddt {

struct PointReadOptions {
  std::vector<std::string> columns;     // empty: x, y, then every other column as values
  std::optional<double> input_nodata;   // drop points with this value (may be NaN)
  bool float_values = false;            // values must fit a 32-bit float (else an error naming the line)
  // More points than this are refused at the line that passes it, named
  // `option` in the message (size_limits.hpp).
  long long max_points = default_max_input_points();
  std::string option = "--max-input-points";
};

struct PointTable {
  std::vector<Point2> points;              // #N positions, in file order
  std::vector<double> values;              // #N by channels, row-major
  int channels = 0;                        // value columns
  std::vector<std::string> channel_names;  // header names, or "value1", "value2", ...
  bool has_header = false;
  char delimiter = ',';                    // ',', ';' or ' ' (runs of blanks)
  long long lines_read = 0;                // data lines (not header, comments, blanks)
  long long dropped_nodata = 0;            // points dropped by input_nodata
};

// Reads `path`; throws ddt::Error (missing file, empty file, malformed line).
PointTable read_point_table(const std::string& path, const PointReadOptions& options = {});

// The same from a stream; `name` is used in messages.
PointTable parse_point_table(std::istream& in, const std::string& name, const PointReadOptions& options = {});

// Merges points at identical positions (exact equality of x and y): the
// first occurrence is kept, in file order, with the mean of the values of
// all points at its position.
struct MergeStats {
  long long removed = 0;    // points folded into another
  long long positions = 0;  // positions that had more than one point
};
MergeStats merge_duplicate_points(PointTable& table);

}  // namespace ddt
