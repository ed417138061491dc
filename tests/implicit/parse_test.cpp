#include "isoforge/implicit/parse.hpp"

#include <gtest/gtest.h>

#include <random>

using namespace isoforge;

namespace {
std::string error_of(const std::string& expr) {
  try {
    (void)parse_implicit(expr);
  } catch (const Error& e) {
    return e.what();
  }
  return "<no error>";
}
}  // namespace

TEST(Parse, PrimitivesWithDefaultsAndNamedParameters) {
  EXPECT_DOUBLE_EQ(parse_implicit("sphere(r=1)").value({2, 0, 0}), 1.0);
  EXPECT_DOUBLE_EQ(parse_implicit("sphere()").value({0, 0, 0}), -1.0);
  EXPECT_DOUBLE_EQ(parse_implicit(" sphere ( center = [1, 0, 0] , radius = 2 ) ").value({1, 0, 0}), -2.0);
  EXPECT_DOUBLE_EQ(parse_implicit("plane(origin=[0,0,1], normal=[0,0,-1])").value({0, 0, 0}), 1.0);
  EXPECT_DOUBLE_EQ(parse_implicit("box(min=[0,0,0], max=[2,2,2])").value({1, 1, 1}), -1.0);
  EXPECT_DOUBLE_EQ(parse_implicit("quadric(a=[1,1,1,0,0,0,0,0,0,-1])").value({0, 0, 0}), -1.0);
  EXPECT_DOUBLE_EQ(parse_implicit("offset(sphere(r=1), 0.5)").value({0, 0, 0}), -1.5);
  EXPECT_DOUBLE_EQ(parse_implicit("translate(sphere(r=1), [3, 0, 0])").value({3, 0, 0}), -1.0);
  EXPECT_DOUBLE_EQ(parse_implicit("scale(sphere(r=1), 2)").value({0, 0, 0}), -1.0);
}

TEST(Parse, PrintThenParseIsBitIdentical) {
  const char* exprs[] = {
      "icecream()",
      "union(scale(sphere(), [1, 0.5, 0.5]), translate(sphere(r=0.5), [1, 0, 0]))",
      "difference(box(min=[-1,-1,-1], max=[1,1,1]), cylinder(axis=[1,0,0], r=0.3333333333333333))",
      "intersection(cone(apex=[0,0,0], axis=[0,1,0], angle=22.5), complement(torus(R=2, r=0.1)))",
      "rotate(superquadric(radii=[1,2,3], n=0.3, e=2.5), axis=[1,2,3], angle=17)",
      "offset(quadric(a=[1,2,3,4,5,6,7,8,9,-10]), d=-0.125)",
  };
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-2, 2);
  for (const char* e : exprs) {
    const ImplicitFunction f = parse_implicit(e);
    const ImplicitFunction g = parse_implicit(f.to_string());
    EXPECT_EQ(g.to_string(), f.to_string()) << e;
    for (int i = 0; i < 100; ++i) {
      const Vec3 p{u(rng), u(rng), u(rng)};
      ASSERT_EQ(f.value(p), g.value(p)) << e;
    }
  }
}

TEST(Parse, ErrorsNameTheColumnOrParameter) {
  EXPECT_NE(error_of("sphere(r=1").find("column 11: expected ')'"), std::string::npos) << error_of("sphere(r=1");
  EXPECT_NE(error_of("sphere(r=-1)").find("'r' (radius) is negative"), std::string::npos);
  EXPECT_NE(error_of("spehre(r=1)").find("unknown function"), std::string::npos);
  EXPECT_NE(error_of("sphere(rr=1)").find("unknown parameter 'rr'"), std::string::npos);
  EXPECT_NE(error_of("sphere(r=1, r=2)").find("given twice"), std::string::npos);
  EXPECT_NE(error_of("sphere(center=[1,2])").find("must be [x, y, z]"), std::string::npos);
  EXPECT_NE(error_of("union()").find("at least one"), std::string::npos);
  EXPECT_NE(error_of("difference(sphere())").find("exactly two"), std::string::npos);
  EXPECT_NE(error_of("cone(angle=95)").find("(0, 90)"), std::string::npos);
  EXPECT_NE(error_of("sphere(r=1e999)").find("finite number"), std::string::npos);
  EXPECT_NE(error_of("sphere() sphere()").find("after the expression"), std::string::npos);
  EXPECT_NE(error_of("").find("expected a name"), std::string::npos);
}
