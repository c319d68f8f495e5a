// Vectors whose resize() leaves trivially constructible elements unwritten: for large
// buffers that a parallel loop then fills. Their pages are then first touched, and zeroed
// by the kernel, by the threads that fill them, instead of all on the one thread that
// resizes (on the sample CT, zero-filling the MPU lookup grid's 9.5 million entries takes
// 0.06-0.08 s on one core).
#pragma once

#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace mpumesh {

// std::allocator, except that construction without arguments default-initialises.
template <class T, class A = std::allocator<T>>
class DefaultInitAllocator : public A {
  using Traits = std::allocator_traits<A>;

 public:
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U, typename Traits::template rebind_alloc<U>>;
  };
  using A::A;

  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    Traits::construct(static_cast<A&>(*this), p, std::forward<Args>(args)...);
  }
};

// Every element must be written before it is read.
template <class T>
using FillVector = std::vector<T, DefaultInitAllocator<T>>;

}  // namespace mpumesh
