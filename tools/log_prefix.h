#pragma once
// The prefix of glog's lines on stderr: warnings and logged errors read
// like the program's own messages ("surfreg: warning: ...": a logged error
// does not end the run, unlike a "surfreg: error: ..." line);
// INFO lines (--minloglevel=0, -v) keep glog's severity, time and source
// location, which is what such logs are for. main passes it to
// google::InitGoogleLogging; glog adds one space after the prefix.
#include <glog/logging.h>

#include <ostream>

namespace surfreg {

void LogPrefix(std::ostream& stream, const google::LogMessageInfo& info, void* data);

}  // namespace surfreg
