// Text point files (.xyz .txt .csv): "x y z [weight]" per line.
#include <cstring>
#include <string>

#include "tools/io/surface_reader_internal.h"

namespace surfreg::io_internal {
namespace {

constexpr int kKeptFields = 5;  // one more than allowed, enough to report the excess
const char* const kColumnName[] = {"x", "y", "z", "weight"};

// The fields of one line, split at runs of blanks and/or one comma.
struct Fields {
  std::string_view token[kKeptFields];
  int count = 0;             // all fields, even beyond kKeptFields
  bool empty_field = false;  // "1,,2", or a comma at the start or end of the line
};

Fields SplitFields(const char* p, const char* end) {
  Fields fields;
  for (;;) {
    int commas = 0;
    while (p < end && (IsBlank(*p) || *p == ',')) commas += *p++ == ',';
    // Between two fields one comma is a separator; anywhere else it delimits
    // an empty field, which would silently shift the columns if ignored.
    if (p == end) {
      fields.empty_field |= commas > 0;
      return fields;
    }
    fields.empty_field |= commas > (fields.count > 0 ? 1 : 0);
    const char* start = p;
    while (p < end && !IsBlank(*p) && *p != ',') ++p;
    if (fields.count < kKeptFields) {
      fields.token[fields.count] = std::string_view(start, static_cast<std::size_t>(p - start));
    }
    ++fields.count;
  }
}

std::string Columns(int n) { return n == 4 ? "4 numbers (x y z weight)" : "3 numbers (x y z)"; }

class XyzParser {
 public:
  explicit XyzParser(const std::string& name) : name_(name) {}

  PointList Run(std::string_view data) {
    const char* p = data.data();
    const char* const end = p + data.size();
    if (data.size() >= 3 && std::memcmp(p, "\xEF\xBB\xBF", 3) == 0) p += 3;  // UTF-8 BOM
    std::size_t line = 0;
    while (p < end) {
      ++line;
      const auto* eol =
          static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
      if (eol == nullptr) eol = end;
      const auto* hash =
          static_cast<const char*>(std::memchr(p, '#', static_cast<std::size_t>(eol - p)));
      const Fields fields = SplitFields(p, hash != nullptr ? hash : eol);
      p = eol < end ? eol + 1 : end;
      if (fields.count == 0 && !fields.empty_field) continue;
      if (IsHeader(fields)) continue;
      AddPoint(fields, line);
    }
    return std::move(list_);
  }

 private:
  // Only the first non-comment line may be a header: one whose first field
  // is not a number ("x,y,z", "X Y Z weight").
  bool IsHeader(const Fields& fields) {
    if (!header_allowed_) return false;
    header_allowed_ = false;
    double unused;
    return fields.count > 0 && ParseNumber(fields.token[0], &unused) == NumberStatus::kNotANumber;
  }

  void CheckFieldCount(const Fields& fields, std::size_t line) {
    const int n = fields.count;
    if (fields.empty_field) {
      Fail(name_, line, "empty field (a comma at the start or end of the line, or two in a row)");
    }
    if (n != 3 && n != 4) {
      const std::string expected =
          columns_ == 0 ? "3 numbers (x y z) or 4 (x y z weight)" : Columns(columns_);
      Fail(name_, line, "expected " + expected + ", found " + std::to_string(n));
    }
    if (columns_ == 0) {
      columns_ = n;
      columns_line_ = line;
    } else if (n != columns_) {
      Fail(name_, line,
           "expected " + Columns(columns_) + " like line " + std::to_string(columns_line_) +
               ", found " + std::to_string(n));
    }
  }

  void AddPoint(const Fields& fields, std::size_t line) {
    CheckFieldCount(fields, line);
    double value[4];
    for (int k = 0; k < fields.count; ++k) {
      const NumberStatus status = ParseNumber(fields.token[k], &value[k]);
      CheckNumber(status, value[k], fields.token[k], kColumnName[k], name_, line);
    }
    list_.points.push_back({value[0], value[1], value[2]});
    if (fields.count == 4) {
      if (value[3] < 0.0) Fail(name_, line, "weight is negative: " + Quote(fields.token[3]));
      list_.weight.push_back(value[3]);
    }
  }

  const std::string& name_;
  PointList list_;
  bool header_allowed_ = true;
  int columns_ = 0;  // 3 or 4 once the first data line is seen
  std::size_t columns_line_ = 0;
};

}  // namespace

Surface ParseXyz(std::string_view data, const std::string& name, const ReadOptions& options) {
  return Finish(XyzParser(name).Run(data), name, options);
}

}  // namespace surfreg::io_internal
