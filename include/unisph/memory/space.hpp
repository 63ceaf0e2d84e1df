#pragma once
// Where data lives and how an access uses it.

#include <concepts>

namespace unisph {

enum class MemorySpace { host = 0, device = 1 };

// The mode of an access decides what the variable must copy before it and which copy is
// current after it: read needs the current contents and changes nothing; write needs nothing
// (every element will be written) and makes this side the only current one; read_write needs
// the current contents and makes this side the only current one.
enum class Access { read, write, read_write };

// Anything that names the memory space it runs in as `P::space` (the execution policies of
// exec/policy.hpp): variables give views in that space without knowing the policies.
template <class P>
concept InMemorySpace = requires {
  { P::space } -> std::convertible_to<MemorySpace>;
};

inline constexpr const char* to_string(MemorySpace s) { return s == MemorySpace::host ? "host" : "device"; }

}  // namespace unisph
