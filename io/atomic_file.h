#pragma once
// Output files that are either complete or absent: the data go to a temporary
// file in the destination's directory (so the final rename stays on one file
// system and is atomic), which is renamed over the destination only once
// every byte is written and closed. No fsync: this guards against partial
// files from errors and interrupted runs, not against power loss.
#include <string>
#include <string_view>

namespace surfreg {

// Throws InputError unless `path` can be an output file: its directory
// exists and is a directory, and `path` itself is not a directory. `label`
// says where the path came from (e.g. "t.yaml:4: key 'output'") and starts
// the message. Lets a command fail before long work rather than after it.
void CheckOutputPath(const std::string& path, const std::string& label);

// Whether two paths name one file: the same text, or (both existing) the
// same device and inode. So that an output never overwrites an input.
bool SameFile(const std::string& a, const std::string& b);

// Writes `data` to `path` atomically (see above); the file gets mode 0666
// less the umask, like any new file. On any failure (missing directory, full
// disk, rename refused) the temporary file is removed, an existing file at
// `path` is left unchanged, and InputError names `label` and `path`.
void WriteFileAtomically(const std::string& path, std::string_view data, const std::string& label);

}  // namespace surfreg
