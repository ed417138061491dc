#include "isoforge/implicit/parse.hpp"

#include <gtest/gtest.h>

#include <random>

#include "isoforge/implicit/sample.hpp"
#include "support/expect_error.hpp"

using namespace isoforge;

namespace {
std::string error_of(const std::string& expr) {
  return test::error_message([&] { (void)parse_implicit(expr); });
}

// `inner` inside `levels` nested calls: open + ... + open + inner + close + ... + close.
std::string nested(const std::string& open, const std::string& close, int levels,
                   const std::string& inner) {
  std::string s;
  for (int i = 0; i < levels; ++i) s += open;
  s += inner;
  for (int i = 0; i < levels; ++i) s += close;
  return s;
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
      // Directions that are not unit vectors (found by fuzz_function): the print used to give
      // the normalized vector, and normalizing it again changed its last bits.
      "plane(origin=[0,0,1], normal=[1,0,-1])",
      "union(cylinder(axis=[1,1,0], r=0.5), cone(axis=[0,3,4], angle=30), torus(axis=[1,2,2]))",
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

TEST(Parse, NestingDeeperThanTheLimitIsAnErrorNotACrash) {
  // Parsing, evaluating, bounding and printing recurse once per level: a thousand nested
  // complements used to overflow the stack. The 101st call is refused where it opens, at column
  // 1 + 100 * strlen("complement(") = 1101.
  const std::string deep = error_of(nested("complement(", ")", 1000, "sphere()"));
  EXPECT_NE(deep.find("function expression: column 1101: complement: nested more than 100 levels "
                      "deep (the limit)"),
            std::string::npos)
      << deep;
  EXPECT_NE(error_of(nested("complement(", ")", 100, "sphere()")).find("column 1101"),
            std::string::npos);
  // In the 100th union, its first operand opens the 101st level: column 1 + 99 * 16 + 6.
  EXPECT_NE(error_of(nested("union(sphere(), ", ")", 100, "box()")).find("column 1591: sphere"),
            std::string::npos);
  // icecream() is itself 3 levels deep (union, intersection, cone): 98 complements around it make
  // 101 levels, refused by the function tree itself.
  const std::string ice = error_of(nested("complement(", ")", 98, "icecream()"));
  EXPECT_NE(ice.find("complement: the function would be nested 101 levels deep; the limit is 100"),
            std::string::npos)
      << ice;
}

TEST(Parse, FunctionsAtTheDepthLimitEvaluateEverywhere) {
  // 99 translations by zero around a sphere: 100 levels, the deepest allowed, and transforms are
  // the levels with the largest stack frames (three blocks of coordinates each). Point values,
  // gradients, bounds, batches, printing and the multi-threaded sampler (which evaluates on TBB
  // worker stacks, with pruning) all work and give the sphere's values bit for bit.
  const ImplicitFunction f = parse_implicit(nested("translate(", ", [0, 0, 0])", 99, "sphere(r=0.75)"));
  const ImplicitFunction s = ImplicitFunction::sphere({0, 0, 0}, 0.75);
  EXPECT_EQ(f.depth(), kMaxFunctionDepth);
  for (const Vec3 p : {Vec3{0, 0, 0}, Vec3{0.3, -0.2, 0.9}, Vec3{-1.5, 2, 0.25}}) {
    EXPECT_EQ(f.value(p), s.value(p));
    const Vec3 gf = f.gradient(p), gs = s.gradient(p);
    EXPECT_EQ(gf.x, gs.x);
    EXPECT_EQ(gf.y, gs.y);
    EXPECT_EQ(gf.z, gs.z);
  }
  const Bounds box{{-0.5, -0.25, 0}, {1, 0.5, 0.75}};
  EXPECT_EQ(f.bound(box).lo, s.bound(box).lo);
  EXPECT_EQ(f.bound(box).hi, s.bound(box).hi);
  EXPECT_EQ(parse_implicit(f.to_string()).depth(), kMaxFunctionDepth);

  const GridSpec grid = GridSpec::from_bounds({{-1, -1, -1}, {1, 1, 1}}, {40, 40, 40});
  const ImageData a = sample_image(f, grid), b = sample_image(s, grid);
  EXPECT_TRUE(a.point_data.get("F") == b.point_data.get("F"));

  // 99 complements: the sphere negated (an odd number of them).
  const ImplicitFunction c = parse_implicit(nested("complement(", ")", 99, "sphere(r=0.75)"));
  EXPECT_EQ(c.depth(), kMaxFunctionDepth);
  EXPECT_EQ(c.value({0.1, 0.2, 0.3}), -s.value({0.1, 0.2, 0.3}));
}
