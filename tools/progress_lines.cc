#include "tools/progress_lines.h"

#include <sys/stat.h>

#include <cstdio>

namespace surfreg {
namespace {

double Bytes(const std::vector<std::string>& files) {
  double total = 0;
  for (const std::string& file : files) {
    struct stat info;
    if (::stat(file.c_str(), &info) == 0 && S_ISREG(info.st_mode)) total += static_cast<double>(info.st_size);
  }
  return total;
}

}  // namespace

bool LargeInputs(const std::vector<std::string>& files, double bytes) { return Bytes(files) >= bytes; }

void PrintReadingLine(const char* command, const std::vector<std::string>& files) {
  std::string names;
  for (std::size_t i = 0; i < files.size(); ++i) {
    names += (i == 0 ? "" : i + 1 == files.size() ? " and " : ", ") + files[i];
  }
  std::fprintf(stderr, "%s: reading %s (%.1f MB)\n", command, names.c_str(), Bytes(files) / 1e6);
}

}  // namespace surfreg
