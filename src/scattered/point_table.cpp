// Reading point tables. Delimited text goes through libcsv (Debian
// libcsv-dev), an RFC 4180 tokenizer, fed one physical line at a time so
// every message can name its line. Alternatives considered:
//   - fast-cpp-csv-parser (libfccp-dev): the column count is a template
//     parameter and a header is required, but extra value columns must
//     become extra channels at run time; it also does not accept NaN/inf in
//     a way we could report, and its float parser is not correctly rounded.
//   - GDAL/OGR: a very large dependency for three numbers per line; its CSV
//     driver needs the geometry columns named in open options, and its XYZ
//     driver reads regular grids only (not scattered points), without the
//     line-numbered errors asked for here.
// Whitespace-separated files (ASCII XYZ) have no quoting rules: a run of
// blanks separates fields by the format's definition, so they are split
// here directly. Numbers are converted with std::from_chars.

#include "scattered/point_table.hpp"

#include "util/error.hpp"
#include "io/safe_file.hpp"
#include "util/text.hpp"

#include <csv.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <numeric>
#include <string_view>

namespace ddt {
namespace {

bool is_blank(char c) { return c == ' ' || c == '\t'; }

// Shortens a field for a message and keeps it on one line.
std::string quoted_field(std::string_view s) {
  std::string out(s.substr(0, 40));
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 0x20) c = '?';
  if (s.size() > 40) out += "...";
  return "'" + out + "'";
}

enum class NumberStatus { ok, not_a_number, out_of_range };

// A whole field as a double: optional sign ('+' too), digits, point,
// exponent; also "nan" and "inf", which the caller rejects or drops.
NumberStatus parse_number(std::string_view s, double& out) {
  if (!s.empty() && s.front() == '+' && s.size() > 1 && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
  if (s.empty()) return NumberStatus::not_a_number;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out, std::chars_format::general);
  if (ec == std::errc::result_out_of_range) return NumberStatus::out_of_range;
  if (ec != std::errc() || end != s.data() + s.size()) return NumberStatus::not_a_number;
  return NumberStatus::ok;
}

// libcsv, one line at a time: the fields of one record.
class CsvLine {
 public:
  explicit CsvLine(char delimiter) {
    if (csv_init(&parser_, CSV_STRICT | CSV_STRICT_FINI | CSV_APPEND_NULL) != 0) throw std::bad_alloc();
    csv_set_delim(&parser_, static_cast<unsigned char>(delimiter));
  }
  ~CsvLine() { csv_free(&parser_); }
  CsvLine(const CsvLine&) = delete;
  CsvLine& operator=(const CsvLine&) = delete;

  // Splits `line` into `fields`; returns an empty string or what is wrong.
  std::string split(std::string_view line, std::vector<std::string>& fields) {
    fields.clear();
    records_ = 0;
    Sink sink{&fields, &records_};
    const std::size_t used = csv_parse(&parser_, line.data(), line.size(), on_field, on_record, &sink);
    if (used != line.size()) {
      csv_fini(&parser_, nullptr, nullptr, nullptr);  // reset for the next line
      return "malformed CSV quoting near column " + std::to_string(used + 1);
    }
    if (csv_fini(&parser_, on_field, on_record, &sink) != 0) return "unterminated quoted field";
    if (records_ > 1) return "stray carriage return inside the line";
    return {};
  }

 private:
  struct Sink {
    std::vector<std::string>* fields;
    int* records;
  };
  static void on_field(void* s, std::size_t len, void* data) {
    static_cast<Sink*>(data)->fields->emplace_back(s ? static_cast<const char*>(s) : "", s ? len : 0);
  }
  static void on_record(int, void* data) { ++*static_cast<Sink*>(data)->records; }

  csv_parser parser_{};
  int records_ = 0;
};

void split_blanks(std::string_view line, std::vector<std::string>& fields) {
  fields.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_blank(line[i])) ++i;
    const std::size_t begin = i;
    while (i < line.size() && !is_blank(line[i])) ++i;
    if (i > begin) {
      std::string_view f = line.substr(begin, i - begin);
      if (f.size() >= 2 && f.front() == '"' && f.back() == '"') f = f.substr(1, f.size() - 2);
      fields.emplace_back(f);
    }
  }
}

// The field indices for x, y and the values, from `columns` or the default.
void resolve_columns(const PointReadOptions& options, const std::vector<std::string>& header, int field_count,
                     std::vector<int>& selected, const std::string& where) {
  selected.clear();
  if (options.columns.empty()) {
    if (field_count < 3)
      throw Error(where + std::to_string(field_count) + (field_count == 1 ? " field" : " fields") +
                  "; need x, y and at least one value (or pick columns with --columns)");
    selected.resize(field_count);
    std::iota(selected.begin(), selected.end(), 0);
    return;
  }
  if (options.columns.size() < 3) throw Error("--columns needs x, y and at least one value column");
  for (const std::string& name : options.columns) {
    int index = -1;
    const bool numeric = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (numeric) {
      index = std::atoi(name.c_str()) - 1;
      if (name.size() > 9 || index < 0 || index >= field_count)
        throw Error(where + "--columns asks for column " + name + " but lines have " + std::to_string(field_count) +
                    " fields");
    } else {
      if (header.empty()) throw Error(where + "no header line to find column '" + name + "' in; give column numbers");
      for (int k = 0; k < field_count; ++k)
        if (lower(header[k]) == lower(name)) {
          index = k;
          break;
        }
      if (index < 0) throw Error(where + "no column named '" + name + "' in the header");
    }
    if (std::find(selected.begin(), selected.end(), index) != selected.end())
      throw Error("--columns names column " + std::to_string(index + 1) + " twice");
    selected.push_back(index);
  }
}

// A line longer than this is no point record (a file with no newlines,
// a sparse file): refused rather than read into memory without bound.
constexpr std::size_t max_line_bytes = 1 << 20;

// std::getline without its unbounded growth: false at the end of the
// input, throws naming the line when it passes max_line_bytes.
bool read_line(std::istream& in, std::string& line, long long line_no, const std::string& name) {
  line.clear();
  std::streambuf* buf = in.rdbuf();
  for (;;) {
    const int c = buf->sbumpc();
    if (c == std::char_traits<char>::eof()) {
      in.setstate(std::ios::eofbit);
      return !line.empty();
    }
    if (c == '\n') return true;
    if (line.size() >= max_line_bytes)
      throw Error("cannot read '" + name + "', line " + std::to_string(line_no) + ": longer than " +
                  std::to_string(max_line_bytes >> 20) + " MiB (not a text table?)");
    line.push_back(static_cast<char>(c));
  }
}

}  // namespace

PointTable parse_point_table(std::istream& in, const std::string& name, const PointReadOptions& options) {
  PointTable table;
  std::vector<std::string> fields, header;
  std::vector<int> selected;  // file field index of x, y, value 1, value 2, ...
  std::unique_ptr<CsvLine> csv;
  int field_count = 0;
  bool layout_known = false;
  std::vector<double> row;
  std::string line;
  long long line_no = 0;
  const bool drop_nan = options.input_nodata && std::isnan(*options.input_nodata);

  while (read_line(in, line, line_no + 1, name)) {
    ++line_no;
    auto where = [&] { return "cannot read '" + name + "', line " + std::to_string(line_no) + ": "; };
    std::string_view text(line);
    if (line_no == 1 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
    if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
    const std::size_t first = text.find_first_not_of(" \t");
    if (first == std::string_view::npos || text[first] == '#') continue;

    if (!layout_known) {
      if (text.find(',') != std::string_view::npos) table.delimiter = ',';
      else if (text.find(';') != std::string_view::npos) table.delimiter = ';';
      else table.delimiter = ' ';
      if (table.delimiter != ' ') csv = std::make_unique<CsvLine>(table.delimiter);
    }
    if (csv) {
      const std::string problem = csv->split(text, fields);
      if (!problem.empty()) throw Error(where() + problem);
    } else {
      split_blanks(text, fields);
    }

    if (!layout_known) {
      layout_known = true;
      field_count = static_cast<int>(fields.size());
      double probe = 0;
      if (fields.empty() || parse_number(fields[0], probe) == NumberStatus::not_a_number) {
        table.has_header = true;
        header = fields;
      }
      resolve_columns(options, header, field_count, selected, where());
      table.channels = static_cast<int>(selected.size()) - 2;
      for (int k = 0; k < table.channels; ++k) {
        const int col = selected[k + 2];
        table.channel_names.push_back(table.has_header && !header[col].empty() ? header[col]
                                                                                : "value" + std::to_string(k + 1));
      }
      row.resize(selected.size());
      if (table.has_header) continue;
    }

    if (static_cast<int>(fields.size()) != field_count)
      throw Error(where() + std::to_string(fields.size()) + (fields.size() == 1 ? " field" : " fields") + ", expected " +
                  std::to_string(field_count) + " like the " + (table.has_header ? "header" : "first line"));
    bool drop = false;
    for (std::size_t k = 0; k < selected.size(); ++k) {
      const int col = selected[k];
      const std::string& f = fields[col];
      auto label = [&] {
        std::string l = "field " + std::to_string(col + 1);
        if (table.has_header && !header[col].empty()) l += " (" + header[col] + ")";
        return l;
      };
      if (f.empty()) throw Error(where() + label() + " is empty");
      const NumberStatus status = parse_number(f, row[k]);
      if (status == NumberStatus::out_of_range) throw Error(where() + label() + " " + quoted_field(f) + " is out of range");
      if (status != NumberStatus::ok) {
        const bool decimal_comma = table.delimiter == ';' && f.find(',') != std::string::npos;
        throw Error(where() + label() + " " + quoted_field(f) + " is not a number" +
                    (decimal_comma ? " (decimal commas are not supported)" : ""));
      }
      if (k >= 2 && options.input_nodata && (row[k] == *options.input_nodata || (drop_nan && std::isnan(row[k])))) {
        drop = true;
        continue;
      }
      if (!std::isfinite(row[k])) throw Error(where() + label() + " " + quoted_field(f) + " is not a finite number");
      if (k >= 2 && options.float_values && std::abs(row[k]) > std::numeric_limits<float>::max())
        throw Error(where() + label() + " " + quoted_field(f) + " is beyond the 32-bit float range");
    }
    ++table.lines_read;
    if (drop) {
      ++table.dropped_nodata;
      continue;
    }
    if (static_cast<long long>(table.points.size()) >= options.max_points)
      throw Error(where() + "more than " + std::to_string(options.max_points) + " points (" + options.option + ")");
    table.points.push_back({row[0], row[1]});
    table.values.insert(table.values.end(), row.begin() + 2, row.end());
  }
  if (in.bad()) throw Error("cannot read '" + name + "': read error");
  if (table.lines_read == 0)
    throw Error("cannot read '" + name + "': no points" +
                (table.has_header ? " (only a header line)" : layout_known ? "" : " (the file is empty)"));
  if (table.points.empty())
    throw Error("cannot read '" + name + "': every point has the input no-data value");
  return table;
}

PointTable read_point_table(const std::string& path, const PointReadOptions& options) {
  check_regular_file(path);  // a FIFO would block the open, a device never end
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read '" + path + "': permission denied or unreadable");
  return parse_point_table(in, path, options);
}

MergeStats merge_duplicate_points(PointTable& table) {
  MergeStats stats;
  const std::size_t n = table.points.size();
  const int C = table.channels;
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  const auto& P = table.points;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (P[a].x != P[b].x) return P[a].x < P[b].x;
    if (P[a].y != P[b].y) return P[a].y < P[b].y;
    return a < b;
  });
  std::vector<char> keep(n, 1);
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i + 1;
    while (j < n && P[order[j]].x == P[order[i]].x && P[order[j]].y == P[order[i]].y) ++j;
    if (j - i > 1) {
      ++stats.positions;
      stats.removed += static_cast<long long>(j - i - 1);
      const std::size_t first = order[i];  // smallest index: sorted by index within a position
      for (int c = 0; c < C; ++c) {
        double sum = 0;
        for (std::size_t k = i; k < j; ++k) sum += table.values[order[k] * C + c];
        table.values[first * C + c] = sum / static_cast<double>(j - i);
      }
      for (std::size_t k = i + 1; k < j; ++k) keep[order[k]] = 0;
    }
    i = j;
  }
  if (stats.removed == 0) return stats;
  std::size_t out = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!keep[i]) continue;
    table.points[out] = table.points[i];
    std::copy_n(table.values.begin() + static_cast<std::ptrdiff_t>(i * C), C,
                table.values.begin() + static_cast<std::ptrdiff_t>(out * C));
    ++out;
  }
  table.points.resize(out);
  table.values.resize(out * C);
  return stats;
}

}  // namespace ddt
