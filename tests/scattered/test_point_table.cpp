#include "util/error.hpp"
#include "scattered/point_table.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <sstream>
#include <string>

using namespace ddt;

namespace {

PointTable parse(const std::string& text, const PointReadOptions& options = {}) {
  std::istringstream in(text);
  return parse_point_table(in, "p.csv", options);
}

// The message of the ddt::Error that parsing `text` throws, or "" when none.
std::string error_of(const std::string& text, const PointReadOptions& options = {}) {
  try {
    parse(text, options);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("parse_point_table: CSV with a header, extra value columns become channels") {
  const PointTable t = parse("x,y,z,intensity\n0,0,1.5,10\n2.5,-1e3,+2,20\n");
  CHECK(t.has_header);
  CHECK(t.delimiter == ',');
  REQUIRE(t.points.size() == 2);
  CHECK(t.channels == 2);
  CHECK(t.channel_names == std::vector<std::string>{"z", "intensity"});
  CHECK(t.points[1].x == 2.5);
  CHECK(t.points[1].y == -1000.0);
  CHECK(t.values == std::vector<double>{1.5, 10, 2, 20});
}

TEST_CASE("parse_point_table: whitespace-separated XYZ as gdal_translate -of XYZ writes it") {
  const PointTable t = parse("105 45 0\n115 45 0.333333343267440796\n105\t35   1\n");
  CHECK_FALSE(t.has_header);
  CHECK(t.delimiter == ' ');
  REQUIRE(t.points.size() == 3);
  CHECK(t.channel_names == std::vector<std::string>{"value1"});
  CHECK(t.values[1] == 0.333333343267440796);  // correctly rounded
  CHECK(t.points[2].y == 35);
  const PointTable h = parse("X,Y,Z\n105,45,0\n115,45,1\n");  // -co ADD_HEADER_LINE=YES -co COLUMN_SEPARATOR=,
  CHECK(h.has_header);
  CHECK(h.points.size() == 2);
}

TEST_CASE("parse_point_table: comments, blank lines, BOM, CR-LF and semicolons") {
  const PointTable t = parse("\xEF\xBB\xBFx;y;v\r\n# a comment\r\n\r\n  \r\n1;2;3\r\n4;5;6\r\n");
  CHECK(t.delimiter == ';');
  CHECK(t.has_header);
  CHECK(t.lines_read == 2);
  CHECK(t.values == std::vector<double>{3, 6});
}

TEST_CASE("parse_point_table: --columns picks by name or number - quoted text columns are skipped") {
  const std::string text =
      "id,\"name, long\",east,north,elev\n"
      "1,\"Hill, north \"\"A\"\"\",10,20,300\n"
      "2,plain,11,21,301\n";
  PointReadOptions by_name;
  by_name.columns = {"EAST", "north", "elev"};
  const PointTable t = parse(text, by_name);
  REQUIRE(t.points.size() == 2);
  CHECK(t.points[0].x == 10);
  CHECK(t.points[0].y == 20);
  CHECK(t.values == std::vector<double>{300, 301});
  CHECK(t.channel_names == std::vector<std::string>{"elev"});
  PointReadOptions by_number;
  by_number.columns = {"3", "4", "5", "1"};
  const PointTable n = parse(text, by_number);
  CHECK(n.channels == 2);
  CHECK(n.values == std::vector<double>{300, 1, 301, 2});
  by_name.columns = {"east", "north", "height"};
  CHECK(error_of(text, by_name).find("no column named 'height'") != std::string::npos);
  by_number.columns = {"3", "4", "9"};
  CHECK(error_of(text, by_number).find("column 9") != std::string::npos);
}

TEST_CASE("parse_point_table: malformed lines name the file and the line") {
  CHECK(error_of("x,y,z\n0,0,1\n# c\n1,abc,2\n") == "cannot read 'p.csv', line 4: field 2 (y) 'abc' is not a number");
  CHECK(error_of("0,0,1\n1,1\n") == "cannot read 'p.csv', line 2: 2 fields, expected 3 like the first line");
  CHECK(error_of("0 0 1\n1 1 1 1\n") == "cannot read 'p.csv', line 2: 4 fields, expected 3 like the first line");
  CHECK(error_of("0,0,1\n1,1,nan\n") == "cannot read 'p.csv', line 2: field 3 'nan' is not a finite number");
  CHECK(error_of("0,0,1\n1,inf,1\n") == "cannot read 'p.csv', line 2: field 2 'inf' is not a finite number");
  CHECK(error_of("0,0,1\n1,1e999,1\n") == "cannot read 'p.csv', line 2: field 2 '1e999' is out of range");
  PointReadOptions as_float;
  as_float.float_values = true;
  CHECK(error_of("0,0,1\n1,1e300,1e300\n", as_float) ==
        "cannot read 'p.csv', line 2: field 3 '1e300' is beyond the 32-bit float range");
  CHECK(error_of("0,0,1\n1,,1\n") == "cannot read 'p.csv', line 2: field 2 is empty");
  CHECK(error_of("0,0,1\n1,\"2,1\n") == "cannot read 'p.csv', line 2: unterminated quoted field");
  CHECK(error_of("0,0,1\n1,2\"x\",1\n").find("line 2: malformed CSV quoting") != std::string::npos);
  CHECK(error_of("0;0;1\n1,5;2;1\n").find("line 2: field 1 '1,5' is not a number (decimal commas") !=
        std::string::npos);
  CHECK(error_of("0,0\n1,1\n").find("line 1: 2 fields; need x, y and at least one value") != std::string::npos);
  CHECK(error_of("") == "cannot read 'p.csv': no points (the file is empty)");
  CHECK(error_of("x,y,z\n\n") == "cannot read 'p.csv': no points (only a header line)");
}

TEST_CASE("parse_point_table: --input-nodata drops points, NaN included") {
  PointReadOptions o;
  o.input_nodata = -9999;
  const PointTable t = parse("0 0 1\n1 0 -9999\n0 1 2\n", o);
  CHECK(t.points.size() == 2);
  CHECK(t.dropped_nodata == 1);
  o.input_nodata = std::nan("");
  const PointTable n = parse("0,0,1\n1,0,nan\n0,1,2\n", o);
  CHECK(n.points.size() == 2);
  CHECK(n.dropped_nodata == 1);
  // Positions must still be finite.
  CHECK(error_of("0,0,1\nnan,0,1\n", o).find("line 2: field 1 'nan' is not a finite number") != std::string::npos);
}

TEST_CASE("read_point_table: a missing file is a one-line error") {
  CHECK_THROWS_WITH_AS(read_point_table("/nonexistent/p.csv"), "cannot read '/nonexistent/p.csv': no such file", Error);
}

TEST_CASE("merge_duplicate_points: one point per position, values averaged, first occurrence kept in order") {
  PointTable t = parse("x,y,a,b\n1,1,1,10\n0,0,5,50\n1,1,2,20\n2,2,7,70\n1,1,6,60\n0,-0,3,30\n");
  const MergeStats m = merge_duplicate_points(t);
  CHECK(m.removed == 3);
  CHECK(m.positions == 2);
  REQUIRE(t.points.size() == 3);
  CHECK(t.points[0].x == 1);
  CHECK(t.points[1].x == 0);
  CHECK(t.points[2].x == 2);
  CHECK(t.values == std::vector<double>{3, 30, 4, 40, 7, 70});
  const MergeStats none = merge_duplicate_points(t);
  CHECK(none.removed == 0);
  CHECK(t.points.size() == 3);
}
