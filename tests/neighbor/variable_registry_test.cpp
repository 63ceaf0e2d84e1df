// The variable registry: registration by name and tag, flags, type checks with messages that
// name both types, lookups, resizing.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "unisph/core/vector.hpp"
#include "unisph/particles/variable_registry.hpp"

namespace {
using namespace unisph;

inline constexpr VariableTag<double> density{"Density"};
inline constexpr VariableTag<Vec<float, 3>> velocity{"Velocity"};

TEST(HostVariableRegistry, RegistersByNameAndTagWithFlags) {
  VariableRegistry r("particle set 'Water'", 10);
  DiscreteVariable<double>& rho = r.add(density, sortable_output_variable);
  DiscreteVariable<Vec<float, 3>>& v = r.add(velocity, sortable_variable);
  DiscreteVariable<int>& scratch = r.add<int>("Scratch");
  EXPECT_EQ(rho.size(), 10u);
  EXPECT_EQ(&r.get(density), &rho);
  EXPECT_EQ((&r.get<Vec<float, 3>>("Velocity")), &v);
  EXPECT_EQ(r.find<int>("Scratch"), &scratch);
  EXPECT_EQ(r.find<int>("Pressure"), nullptr);
  EXPECT_TRUE(r.contains("Density"));
  EXPECT_EQ(r.names(), (std::vector<std::string>{"Density", "Velocity", "Scratch"}));
  EXPECT_EQ(r.sortable_names(), (std::vector<std::string>{"Density", "Velocity"}));
  EXPECT_EQ(r.output_names(), (std::vector<std::string>{"Density"}));
  EXPECT_EQ(r.entry("Velocity").type_name, "unisph::Vec<float, 3>");
}

TEST(HostVariableRegistry, SameNameSameTypeIsTheSameVariableWithMergedFlags) {
  VariableRegistry r("particle set 'Water'", 4);
  DiscreteVariable<double>& a = r.add<double>("Density", sortable_variable);
  DiscreteVariable<double>& b = r.add<double>("Density", output_variable);
  EXPECT_EQ(&a, &b);
  EXPECT_TRUE(r.entry("Density").flags.sortable);
  EXPECT_TRUE(r.entry("Density").flags.output);
  EXPECT_EQ(r.names().size(), 1u);
}

TEST(HostVariableRegistry, SameNameOtherTypeNamesBothTypes) {
  VariableRegistry r("particle set 'Water'", 4);
  r.add<double>("Density");
  try {
    r.add<float>("Density");
    FAIL() << "registering 'Density' as float after double must throw";
  } catch (const VariableError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("'Density'"), std::string::npos) << m;
    EXPECT_NE(m.find("double"), std::string::npos) << m;
    EXPECT_NE(m.find("float"), std::string::npos) << m;
    EXPECT_NE(m.find("Water"), std::string::npos) << m;
  }
  EXPECT_THROW(r.get<int>("Density"), VariableError);
  EXPECT_THROW(r.find<std::uint32_t>("Density"), VariableError);
}

TEST(HostVariableRegistry, MissingNameListsWhatThereIs) {
  VariableRegistry r("particle set 'Wall'", 4);
  r.add<double>("Density");
  r.add<double>("Pressure");
  try {
    r.get<double>("Mass");
    FAIL();
  } catch (const VariableError& e) {
    EXPECT_NE(std::string(e.what()).find("Density, Pressure"), std::string::npos) << e.what();
  }
}

TEST(HostVariableRegistry, ResizeKeepsContents) {
  VariableRegistry r("particle set 'Water'", 3);
  DiscreteVariable<int>& a = r.add<int>("A");
  a.assign(std::vector<int>{1, 2, 3});
  r.resize(5);
  EXPECT_EQ(r.size(), 5u);
  EXPECT_EQ(a.to_vector(), (std::vector<int>{1, 2, 3, 0, 0}));
  DiscreteVariable<int>& b = r.add<int>("B");
  EXPECT_EQ(b.size(), 5u);
}

}  // namespace
