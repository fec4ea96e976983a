#include "tools/log_prefix.h"

#include <cstdio>
#include <cstring>

namespace surfreg {

void LogPrefix(std::ostream& stream, const google::LogMessageInfo& info, void*) {
  // A logged ERROR does not end the run (Ceres logs its solver's failures
  // so); "surfreg: error:" is kept for the messages that do.
  if (std::strcmp(info.severity, "WARNING") == 0 || std::strcmp(info.severity, "ERROR") == 0) {
    stream << "surfreg: warning:";
  } else {
    // glog's own layout: Lmmdd hh:mm:ss.uuuuuu thread file:line]
    char text[64];
    std::snprintf(text, sizeof(text), "%c%02d%02d %02d:%02d:%02d.%06d %5d ", info.severity[0],
                  info.time.month() + 1, info.time.day(), info.time.hour(), (info.time.min)(),
                  info.time.sec(), static_cast<int>(info.time.usec()), info.thread_id);
    stream << text << info.filename << ':' << info.line_number << ']';
  }
}

}  // namespace surfreg
