#pragma once
// Two independent tasks on two threads: the first here, the second on a
// thread of its own (or both here, in order, when not parallel). An
// exception from either is rethrown once both are done. Internal.
#include <exception>
#include <thread>
#include <utility>

namespace surfreg {

template <typename First, typename Second>
void RunBoth(bool parallel, First&& first, Second&& second) {
  if (!parallel) {
    first();
    second();
    return;
  }
  std::exception_ptr error;
  std::thread worker([&] {
    try {
      second();
    } catch (...) {
      error = std::current_exception();
    }
  });
  try {
    first();
  } catch (...) {
    worker.join();
    throw;
  }
  worker.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace surfreg
