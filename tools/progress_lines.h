#pragma once
// When the commands print progress on stderr (never on stdout): not with
// --quiet; from the start when the input files are large enough that the
// run takes seconds (reading them is the first stage), otherwise only once
// a run has taken a second.
#include <string>
#include <vector>

namespace surfreg {

// True if the files together hold at least `bytes` (5 MB: about 200,000
// text samples of 25 bytes, a second or more of work); missing files count
// as empty.
bool LargeInputs(const std::vector<std::string>& files, double bytes = 5e6);

// "<command>: reading A and B (12.3 MB)" on stderr.
void PrintReadingLine(const char* command, const std::vector<std::string>& files);

}  // namespace surfreg
