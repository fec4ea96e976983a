#pragma once
// A std::vector whose resize() default-initializes new elements: for a
// trivial type that writes nothing. A large array is then first touched
// where it is filled, chunk by chunk on every thread, instead of by a
// serial zeroing pass in resize() that also takes every page fault (two
// 2000² DEMs' per-triangle records are half a gigabyte a side).
#include <algorithm>
#include <cstdint>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#include "measure/tasks.h"

namespace surfreg {

template <typename T>
class DefaultInitAllocator : public std::allocator<T> {
 public:
  template <typename U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  DefaultInitAllocator() = default;
  template <typename U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}  // NOLINT: converting, as std::allocator's

  template <typename U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible<U>::value) {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

template <typename T, typename U>
bool operator==(const DefaultInitAllocator<T>&, const DefaultInitAllocator<U>&) noexcept {
  return true;
}
template <typename T, typename U>
bool operator!=(const DefaultInitAllocator<T>&, const DefaultInitAllocator<U>&) noexcept {
  return false;
}

// For trivial element types only: their new elements hold no value until
// written.
template <typename T>
using UninitializedVector = std::vector<T, DefaultInitAllocator<T>>;

// *v resized to n with every element `value`, by fixed chunks on
// `execution`'s threads (where an UninitializedVector's new pages are then
// first touched).
template <typename Vector>
void AssignInChunks(const Execution& execution, std::size_t n, const typename Vector::value_type& value,
                    Vector* v) {
  v->resize(n);
  const int64_t size = static_cast<int64_t>(n);
  ForEachChunk(execution, size, ChunksFor(size, int64_t{1} << 16), [v, &value](int, int64_t first, int64_t last) {
    std::fill(v->begin() + first, v->begin() + last, value);
  });
}

}  // namespace surfreg
