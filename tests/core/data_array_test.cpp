#include "isoforge/core/data_array.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "isoforge/core/attributes.hpp"

using namespace isoforge;

TEST(DataArray, ZeroFilledWithShape) {
  DataArray a("v", ScalarType::Float64, 3, 4);
  EXPECT_EQ(a.name(), "v");
  EXPECT_EQ(a.type(), ScalarType::Float64);
  EXPECT_EQ(a.components(), 3);
  EXPECT_EQ(a.tuples(), 4u);
  EXPECT_EQ(a.size(), 12u);
  EXPECT_EQ(a.size_bytes(), 96u);
  for (double x : a.values<double>()) EXPECT_EQ(x, 0.0);
}

TEST(DataArray, RejectsBadComponents) {
  EXPECT_THROW(DataArray("x", ScalarType::Float32, 0, 1), Error);
  EXPECT_THROW(DataArray::from_vector<float>("x", 3, {1, 2, 3, 4}), Error);
}

TEST(DataArray, TypedAccessChecksType) {
  auto a = DataArray::from_vector<std::int32_t>("ids", 1, {3, -1, 7});
  EXPECT_EQ(a.type(), ScalarType::Int32);
  EXPECT_EQ(a.values<std::int32_t>()[2], 7);
  EXPECT_THROW((void)a.values<float>(), Error);
  try {
    (void)a.values<double>();
  } catch (const Error& e) {
    // The message names the array and both types.
    EXPECT_NE(std::string(e.what()).find("ids"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("Int32"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("Float64"), std::string::npos);
  }
}

TEST(DataArray, RangePerComponentAndMagnitudeIgnoresNaN) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  auto a = DataArray::from_vector<float>("v", 2, {3, 4, -1, 0, nan, 10});
  auto r0 = a.range(0);
  EXPECT_EQ(r0.first, -1);
  EXPECT_EQ(r0.second, 3);
  auto r1 = a.range(1);
  EXPECT_EQ(r1.first, 0);
  EXPECT_EQ(r1.second, 10);
  auto m = a.range(-1);  // magnitudes 5, 1, NaN (skipped)
  EXPECT_EQ(m.first, 1);
  EXPECT_EQ(m.second, 5);
  DataArray empty("e", ScalarType::UInt8, 1);
  EXPECT_GT(empty.range().first, empty.range().second);
}

TEST(DataArray, GetSetPushBackAndConvert) {
  DataArray a("u", ScalarType::UInt8, 2);
  const double t0[] = {1, 255};
  a.push_back(t0);
  a.set(0, 0, 17.9);  // truncates as a C++ cast does
  EXPECT_EQ(a.get(0, 0), 17);
  EXPECT_EQ(a.get(0, 1), 255);
  const double bad[] = {1};
  EXPECT_THROW(a.push_back(bad), Error);
  auto d = a.converted(ScalarType::Float64);
  EXPECT_EQ(d.type(), ScalarType::Float64);
  EXPECT_EQ(d.values<double>()[1], 255.0);
  EXPECT_EQ(d.name(), "u");
}

TEST(DataArray, ScalarTypeNamesRoundTrip) {
  for (int i = 0; i < 10; ++i) {
    auto t = static_cast<ScalarType>(i);
    EXPECT_EQ(scalar_type_from_name(scalar_type_name(t)), t);
  }
  EXPECT_THROW((void)scalar_type_from_name("Float16"), Error);
}

TEST(Attributes, AddReplaceActiveRemove) {
  Attributes at;
  at.add(DataArray("a", ScalarType::Float32, 1, 2), AttributeRole::Scalars);
  at.add(DataArray("b", ScalarType::Float32, 3, 2), AttributeRole::Vectors);
  ASSERT_EQ(at.size(), 2u);
  EXPECT_EQ(at.scalars()->name(), "a");
  EXPECT_EQ(at.vectors()->name(), "b");
  // Replacing keeps the position and role.
  at.add(DataArray("a", ScalarType::Float64, 1, 2));
  EXPECT_EQ(at[0].type(), ScalarType::Float64);
  EXPECT_EQ(at.scalars()->type(), ScalarType::Float64);
  EXPECT_THROW(at.set_active(AttributeRole::Normals, "zzz"), Error);
  EXPECT_THROW((void)at.get("zzz"), Error);
  EXPECT_TRUE(at.remove("a"));
  EXPECT_EQ(at.scalars(), nullptr);
  EXPECT_FALSE(at.remove("a"));
  EXPECT_NO_THROW(at.validate(2, "point data"));
  EXPECT_THROW(at.validate(3, "point data"), Error);
  EXPECT_THROW(at.add(DataArray("", ScalarType::Float32, 1)), Error);
}
