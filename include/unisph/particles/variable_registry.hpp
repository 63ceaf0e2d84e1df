#pragma once
// VariableRegistry: the named per-particle variables of a particle set, looked up by name (or
// by a typed tag), never by position in a list. Each is registered with its type and flags:
//   sortable  permuted with the particles when they are reordered (positions, velocities...;
//             not scratch arrays recomputed every step)
//   output    written to output files
// Registering a name again with the same type returns the same variable (flags are merged);
// with another type it is an error that names both types.

#include <cxxabi.h>

#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <typeindex>
#include <typeinfo>
#include <vector>

#include "unisph/core/error.hpp"
#include "unisph/memory/discrete_variable.hpp"

namespace unisph {

struct VariableFlags {
  bool sortable = false;
  bool output = false;
};
inline constexpr VariableFlags sortable_variable{true, false};
inline constexpr VariableFlags output_variable{false, true};
inline constexpr VariableFlags sortable_output_variable{true, true};

// A name with its type, so that lookups need no template argument and cannot get it wrong:
//   inline constexpr VariableTag<Real> density{"Density"};   registry.get(density)
template <class T>
struct VariableTag {
  using value_type = T;
  std::string_view name;
};

// "double", "unisph::Vec<float, 3>" — for error messages.
template <class T>
std::string type_name() {
  int status = 0;
  char* demangled = abi::__cxa_demangle(typeid(T).name(), nullptr, nullptr, &status);
  std::string name = status == 0 && demangled ? demangled : typeid(T).name();
  std::free(demangled);
  return name;
}

class VariableRegistry {
 public:
  struct Entry {
    std::unique_ptr<VariableBase> variable;
    std::type_index type;
    std::string type_name;
    VariableFlags flags;
    void (*resize)(VariableBase&, Index);  // the typed resize, reached from the untyped entry
  };

  // `owner` names the registry in error messages ("particle set 'Water'").
  VariableRegistry(std::string owner, Index size) : owner_(std::move(owner)), size_(size) {}

  Index size() const { return size_; }
  const std::string& owner() const { return owner_; }

  template <class T>
  DiscreteVariable<T>& add(const std::string& name, VariableFlags flags = {}) {
    if (auto it = index_.find(name); it != index_.end()) {
      Entry& e = entries_[it->second];
      if (e.type != std::type_index(typeid(T)))
        throw VariableError(owner_ + ": variable '" + name + "' is registered as " + e.type_name +
                            "; it cannot be registered again as " + type_name<T>());
      e.flags.sortable = e.flags.sortable || flags.sortable;
      e.flags.output = e.flags.output || flags.output;
      return static_cast<DiscreteVariable<T>&>(*e.variable);
    }
    entries_.push_back({std::make_unique<DiscreteVariable<T>>(name, size_), std::type_index(typeid(T)),
                        type_name<T>(), flags, &resize_as<T>});
    index_.emplace(name, entries_.size() - 1);
    return static_cast<DiscreteVariable<T>&>(*entries_.back().variable);
  }
  template <class T>
  DiscreteVariable<T>& add(VariableTag<T> tag, VariableFlags flags = {}) {
    return add<T>(std::string(tag.name), flags);
  }

  // nullptr when there is no variable of that name; an error when there is one of another type.
  template <class T>
  DiscreteVariable<T>* find(std::string_view name) {
    auto it = index_.find(name);
    if (it == index_.end()) return nullptr;
    Entry& e = entries_[it->second];
    if (e.type != std::type_index(typeid(T)))
      throw VariableError(owner_ + ": variable '" + std::string(name) + "' is a " + e.type_name + ", not a " +
                          type_name<T>());
    return static_cast<DiscreteVariable<T>*>(e.variable.get());
  }

  template <class T>
  DiscreteVariable<T>& get(std::string_view name) {
    if (DiscreteVariable<T>* v = find<T>(name)) return *v;
    std::string known;
    for (const Entry& e : entries_) known += (known.empty() ? "" : ", ") + e.variable->name();
    throw VariableError(owner_ + " has no variable '" + std::string(name) + "' (it has: " +
                        (known.empty() ? "none" : known) + ")");
  }
  template <class T>
  DiscreteVariable<T>& get(VariableTag<T> tag) {
    return get<T>(tag.name);
  }

  bool contains(std::string_view name) const { return index_.find(name) != index_.end(); }
  const Entry& entry(std::string_view name) const {
    auto it = index_.find(name);
    if (it == index_.end()) throw VariableError(owner_ + " has no variable '" + std::string(name) + "'");
    return entries_[it->second];
  }

  // Names in registration order, all of them or those with a flag.
  std::vector<std::string> names() const { return select([](const Entry&) { return true; }); }
  std::vector<std::string> sortable_names() const { return select([](const Entry& e) { return e.flags.sortable; }); }
  std::vector<std::string> output_names() const { return select([](const Entry& e) { return e.flags.output; }); }

  // f(Entry&) for every variable, in registration order.
  template <class F>
  void for_each(F&& f) {
    for (Entry& e : entries_) f(e);
  }

  // Every variable gets `size` elements (contents kept where they fit).
  void resize(Index size) {
    size_ = size;
    for (Entry& e : entries_) e.resize(*e.variable, size);
  }

 private:
  template <class Pred>
  std::vector<std::string> select(Pred pred) const {
    std::vector<std::string> out;
    for (const Entry& e : entries_)
      if (pred(e)) out.push_back(e.variable->name());
    return out;
  }
  template <class T>
  static void resize_as(VariableBase& v, Index size) {
    static_cast<DiscreteVariable<T>&>(v).resize(size);
  }

  std::string owner_;
  Index size_;
  std::vector<Entry> entries_;
  std::map<std::string, std::size_t, std::less<>> index_;
};

}  // namespace unisph
