// The number of members of an aggregate, at compile time, by trying brace initialisers of
// growing length. A codec that lists a struct's fields by hand can then refuse to compile
// when the struct gains a field the list lacks (distributed/protocol.cpp does for
// RenderSettings). Only for aggregates whose members are not themselves brace-elided
// arrays or nested aggregates initialised from one element each.
#pragma once

#include <cstddef>

namespace multiray {

namespace aggregate_detail {
struct Any {
  template <class T>
  operator T() const;  // declared only: used in unevaluated contexts
};
template <class T, class... A>
constexpr size_t count() {
  if constexpr (requires { T{A{}..., Any{}}; })
    return count<T, A..., Any>();
  else
    return sizeof...(A);
}
}  // namespace aggregate_detail

template <class T>
constexpr size_t aggregate_field_count() {
  return aggregate_detail::count<T>();
}

}  // namespace multiray
