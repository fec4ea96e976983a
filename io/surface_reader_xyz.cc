// Text point files (.xyz .txt .csv): "x y z [weight]" per line, or the
// columns ReadOptions::columns picks.
#include <algorithm>
#include <cctype>
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "io/surface_reader_internal.h"
#include "measure/tasks.h"

namespace surfreg::io_internal {
namespace {

const char* const kColumnName[] = {"x", "y", "z", "weight"};
// The highest position `columns` may pick; fields beyond it are counted but
// not kept, so a line of a billion fields costs no memory.
constexpr int kMaxPosition = 100000;

inline bool IsSeparator(char c) { return c == ',' || c == ';'; }

// The fields of one line, split at runs of blanks and/or one ',' or ';'.
// `token` is the parser's, reused from line to line (no allocation per line
// once it has grown to the widest line).
struct Fields {
  std::vector<std::string_view>* token = nullptr;
  int count = 0;
  bool empty_field = false;  // "1,,2", or a separator at the start or end of the line
};

void SplitFields(const char* p, const char* end, Fields* fields) {
  fields->token->clear();
  fields->count = 0;
  fields->empty_field = false;
  for (;;) {
    int separators = 0;
    while (p < end && (IsBlank(*p) || IsSeparator(*p))) separators += IsSeparator(*p++);
    // Between two fields one separator is a separator; anywhere else it
    // delimits an empty field, which would silently shift the columns if ignored.
    if (p == end) {
      fields->empty_field |= separators > 0;
      return;
    }
    fields->empty_field |= separators > (fields->count > 0 ? 1 : 0);
    const char* start = p;
    while (p < end && !IsBlank(*p) && !IsSeparator(*p)) ++p;
    if (fields->count < kMaxPosition) {
      fields->token->emplace_back(start, static_cast<std::size_t>(p - start));
    }
    ++fields->count;
  }
}

std::string Numbers(int n) { return n == 4 ? "4 numbers (x y z weight)" : "3 numbers (x y z)"; }

bool SameName(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char p, char q) {
           return std::tolower(static_cast<unsigned char>(p)) ==
                  std::tolower(static_cast<unsigned char>(q));
         });
}

class XyzParser {
 public:
  XyzParser(const std::string& name, const std::vector<std::string>& columns)
      : name_(name), columns_(columns) {
    fields_.token = &tokens_;
    if (columns.empty()) return;
    if (columns.size() != 3 && columns.size() != 4) {
      Fail(name_, 0,
           "columns: expected 3 or 4 columns (x, y, z and optionally weight), got " +
               std::to_string(columns.size()));
    }
    for (std::size_t k = 0; k < columns.size(); ++k) {
      unsigned long long position = 0;
      if (ParseCount(columns[k], &position)) {
        if (position == 0 || position > kMaxPosition) {
          Fail(name_, 0,
               "columns: position " + Quote(columns[k]) + " is not 1 to " +
                   std::to_string(kMaxPosition) + " (1-based)");
        }
        pick_[k] = static_cast<int>(position - 1);
      } else if (columns[k].empty()) {
        Fail(name_, 0, std::string("columns: the ") + kColumnName[k] + " column is empty");
      } else {
        by_name_ = true;
      }
    }
    picked_ = static_cast<int>(columns.size());
  }

  // A copy carries the state a chunk of later lines needs (the header's
  // picks, the first data line's width); its token list is its own.
  XyzParser(const XyzParser& other) : XyzParser(other.name_, other.columns_) {
    std::copy(other.pick_, other.pick_ + 4, pick_);
    picked_ = other.picked_;
    by_name_ = other.by_name_;
    header_fields_ = other.header_fields_;
    header_line_ = other.header_line_;
    width_ = other.width_;
    width_line_ = other.width_line_;
    header_allowed_ = other.header_allowed_;
    numbers_ = other.numbers_;
    numbers_line_ = other.numbers_line_;
  }
  XyzParser& operator=(const XyzParser&) = delete;

  // Parses `data`, whose first line is line `first_line` of the file; with
  // `stop_after_point`, only up to the end of the first line that held a
  // point. Returns the number of bytes parsed.
  std::size_t Run(std::string_view data, std::size_t first_line, bool stop_after_point) {
    const char* const begin = data.data();
    const char* p = begin;
    const char* const end = p + data.size();
    if (first_line == 1 && data.size() >= 3 && std::memcmp(p, "\xEF\xBB\xBF", 3) == 0) p += 3;  // UTF-8 BOM
    std::size_t line = first_line - 1;
    while (p < end) {
      ++line;
      const auto* eol =
          static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
      if (eol == nullptr) eol = end;
      const auto* hash =
          static_cast<const char*>(std::memchr(p, '#', static_cast<std::size_t>(eol - p)));
      SplitFields(p, hash != nullptr ? hash : eol, &fields_);
      p = eol < end ? eol + 1 : end;
      if (fields_.count == 0 && !fields_.empty_field) continue;
      if (IsHeader(line)) continue;
      if (picked_ == 0) {
        AddPoint(line);
      } else {
        AddPicked(line);
      }
      if (stop_after_point) break;
    }
    return static_cast<std::size_t>(p - begin);
  }

  PointList& list() { return list_; }

 private:
  // Only the first non-comment line may be a header: one whose first field
  // is not a number ("x,y,z", "X Y Z weight"). Its names are what `columns`
  // may pick by.
  bool IsHeader(std::size_t line) {
    if (!header_allowed_) return false;
    header_allowed_ = false;
    double unused;
    if (fields_.count == 0 || ParseNumber(tokens_[0], &unused) != NumberStatus::kNotANumber) {
      if (by_name_) {
        Fail(name_, line,
             "columns names a column (" + Quote(FirstName()) +
                 ") but the file has no header line (its first line is numbers); give "
                 "positions, e.g. columns: 1,2,3");
      }
      return false;
    }
    if (fields_.empty_field) {
      Fail(name_, line, "empty field in the header line (two separators in a row?)");
    }
    if (by_name_) ResolveNames(line);
    return true;
  }

  std::string FirstName() const {
    for (std::size_t k = 0; k < columns_.size(); ++k) {
      if (pick_[k] < 0) return columns_[k];
    }
    return "";
  }

  void ResolveNames(std::size_t line) {
    const int kept = static_cast<int>(tokens_.size());
    for (std::size_t k = 0; k < columns_.size(); ++k) {
      if (pick_[k] >= 0) continue;
      for (int i = 0; i < kept && pick_[k] < 0; ++i) {
        if (SameName(tokens_[i], columns_[k])) pick_[k] = i;
      }
      if (pick_[k] < 0) {
        std::string names;  // Quote shows the start of it
        for (int i = 0; i < kept && names.size() < 200; ++i) {
          names += (i ? ", " : "") + std::string(tokens_[i]);
        }
        Fail(name_, line,
             "columns: no column " + Quote(columns_[k]) + " in the header line (" +
                 Quote(names) + ")");
      }
    }
    header_fields_ = fields_.count;
    header_line_ = line;
  }

  // `columns` given: the picked fields of a line as wide as the first data
  // line (and the header, if names picked); the others are not looked at.
  void AddPicked(std::size_t line) {
    const int n = fields_.count;
    if (fields_.empty_field) {
      Fail(name_, line, "empty field (a separator at the start or end of the line, or two in a row)");
    }
    if (header_fields_ > 0 && n != header_fields_) {
      Fail(name_, line,
           "found " + std::to_string(n) + " columns, the header line " +
               std::to_string(header_line_) + " names " + std::to_string(header_fields_));
    }
    if (width_ == 0) {
      const int highest = *std::max_element(pick_, pick_ + picked_);
      if (highest >= n) {
        Fail(name_, line,
             "columns picks column " + std::to_string(highest + 1) + ", but the line has " +
                 std::to_string(n));
      }
      width_ = n;
      width_line_ = line;
    } else if (n != width_) {
      Fail(name_, line,
           "found " + std::to_string(n) + " columns, line " + std::to_string(width_line_) +
               " has " + std::to_string(width_));
    }
    double value[4];
    for (int k = 0; k < picked_; ++k) {
      const std::string_view token = tokens_[static_cast<std::size_t>(pick_[k])];
      const NumberStatus status = ParseNumber(token, &value[k]);  // before value[k] is read
      CheckNumber(status, value[k], token, kColumnName[k], name_, line);
    }
    Store(value, picked_ == 4 ? tokens_[static_cast<std::size_t>(pick_[3])] : "", line);
  }

  void CheckFieldCount(std::size_t line) {
    const int n = fields_.count;
    if (fields_.empty_field) {
      Fail(name_, line, "empty field (a separator at the start or end of the line, or two in a row)");
    }
    if (n != 3 && n != 4) {
      const std::string expected =
          numbers_ == 0 ? "3 numbers (x y z) or 4 (x y z weight)" : Numbers(numbers_);
      std::string found = "found " + std::to_string(n);
      if (n > 4) {
        found += " columns; give `columns` (e.g. columns: 1,2,3) to pick x, y, z";
      }
      Fail(name_, line, "expected " + expected + ", " + found);
    }
    if (numbers_ == 0) {
      numbers_ = n;
      numbers_line_ = line;
    } else if (n != numbers_) {
      Fail(name_, line,
           "expected " + Numbers(numbers_) + " like line " + std::to_string(numbers_line_) +
               ", found " + std::to_string(n));
    }
  }

  void AddPoint(std::size_t line) {
    CheckFieldCount(line);
    double value[4];
    for (int k = 0; k < fields_.count; ++k) {
      const NumberStatus status = ParseNumber(tokens_[k], &value[k]);  // before value[k] is read
      CheckNumber(status, value[k], tokens_[k], kColumnName[k], name_, line);
    }
    Store(value, fields_.count == 4 ? tokens_[3] : "", line);
  }

  // value[3] is the weight when `weight` (its text) is not empty.
  void Store(const double* value, std::string_view weight, std::size_t line) {
    list_.points.push_back({value[0], value[1], value[2]});
    if (weight.empty()) return;
    if (value[3] < 0.0) Fail(name_, line, "weight is negative: " + Quote(weight));
    list_.weight.push_back(value[3]);
  }

  const std::string& name_;
  const std::vector<std::string>& columns_;
  int pick_[4] = {-1, -1, -1, -1};  // 0-based field of x, y, z, weight (when `columns`)
  int picked_ = 0;                  // 0 (no `columns`), 3 or 4
  bool by_name_ = false;
  int header_fields_ = 0;  // fields of the header line, when names were resolved in it
  std::size_t header_line_ = 0;
  int width_ = 0;  // fields of the first data line (with `columns`)
  std::size_t width_line_ = 0;
  std::vector<std::string_view> tokens_;
  Fields fields_;
  PointList list_;
  bool header_allowed_ = true;
  int numbers_ = 0;  // 3 or 4 once the first data line is seen (no `columns`)
  std::size_t numbers_line_ = 0;
};

}  // namespace

Surface ParseXyz(std::string_view data, const std::string& name, const ReadOptions& options) {
  // The lines up to the first point, then the rest in chunks of lines (from
  // the size only), each parsed by a copy of the parser as it stood; the
  // first error in file order is the one reported, as when parsed in one go.
  XyzParser head(name, options.columns);
  const std::size_t head_bytes = head.Run(data, 1, /*stop_after_point=*/true);
  const std::string_view rest = data.substr(head_bytes);
  const std::size_t head_lines =
      static_cast<std::size_t>(std::count(data.begin(), data.begin() + head_bytes, '\n'));
  const int64_t size = static_cast<int64_t>(rest.size());
  const int chunks = ChunksFor(size, int64_t{4} << 20);
  std::vector<std::size_t> start(chunks + 1, rest.size()), lines(chunks, 0);
  start[0] = 0;
  for (int c = 1; c < chunks; ++c) {
    const std::size_t cut = rest.find('\n', static_cast<std::size_t>(ChunkBegin(size, chunks, c)));
    start[c] = cut == std::string_view::npos ? rest.size() : std::max(start[c - 1], cut + 1);
  }
  std::vector<std::unique_ptr<XyzParser>> parser(chunks);
  std::vector<std::exception_ptr> error(chunks);
  const Execution execution = ExecutionFor(options.threads);
  ForEachChunk(execution, chunks, chunks, [&](int c, int64_t, int64_t) {
    lines[c] = static_cast<std::size_t>(std::count(rest.begin() + start[c], rest.begin() + start[c + 1], '\n'));
  });
  std::vector<std::size_t> first_line(chunks, head_lines + 1);
  for (int c = 1; c < chunks; ++c) first_line[c] = first_line[c - 1] + lines[c - 1];
  ForEachChunk(execution, chunks, chunks, [&](int c, int64_t, int64_t) {
    try {
      parser[c] = std::make_unique<XyzParser>(head);
      parser[c]->Run(rest.substr(start[c], start[c + 1] - start[c]), first_line[c], false);
    } catch (...) {
      error[c] = std::current_exception();
    }
  });
  for (const std::exception_ptr& e : error) {
    if (e) std::rethrow_exception(e);
  }
  PointList all = std::move(head.list());
  std::size_t points = all.points.size(), weights = all.weight.size();
  for (const auto& p : parser) {
    points += p->list().points.size();
    weights += p->list().weight.size();
  }
  all.points.reserve(points);
  all.weight.reserve(weights);
  for (const auto& p : parser) {
    all.points.insert(all.points.end(), p->list().points.begin(), p->list().points.end());
    all.weight.insert(all.weight.end(), p->list().weight.begin(), p->list().weight.end());
  }
  return Finish(std::move(all), name, options);
}

}  // namespace surfreg::io_internal
