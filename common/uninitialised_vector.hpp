#pragma once
// A std::vector whose resize() leaves the new elements default-initialised,
// which for arithmetic types means not written at all: for buffers that the
// code writes whole before it reads them, where std::vector's resize would
// zero every element first (a pass over memory that is written again at
// once, and at a refinement event's first touch of a fresh table a page
// fault more in that pass). assign(n, value), push_back and copies behave as
// std::vector's.
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace pd {

template <class T, class Base = std::allocator<T>>
class DefaultInitAllocator : public Base {
  using Traits = std::allocator_traits<Base>;

public:
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U, typename Traits::template rebind_alloc<U>>;
  };
  using Base::Base;
  DefaultInitAllocator() = default;
  template <class U, class B>
  DefaultInitAllocator(const DefaultInitAllocator<U, B>& other) noexcept : Base(other) {}

  // No value given: default-initialised (an arithmetic element keeps whatever
  // the memory held).
  template <class U>
  void construct(U* at) noexcept(std::is_nothrow_default_constructible<U>::value) {
    ::new (static_cast<void*>(at)) U;
  }
  template <class U, class... Args>
  void construct(U* at, Args&&... args) {
    Traits::construct(static_cast<Base&>(*this), at, std::forward<Args>(args)...);
  }
};

template <class T>
using UninitialisedVector = std::vector<T, DefaultInitAllocator<T>>;

}  // namespace pd
