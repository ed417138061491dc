#include "isoforge/implicit/function.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "isoforge/implicit/parse.hpp"
#include "support/expect_error.hpp"

using namespace isoforge;
using isoforge::test::error_message;
using F = ImplicitFunction;

namespace {


std::vector<std::pair<std::string, F>> catalogue() {
  return {
      {"plane", F::plane({0.1, 0.2, 0.3}, {1, 2, 2})},
      {"sphere", F::sphere({0.5, -0.25, 0}, 0.75)},
      {"cylinder", F::cylinder({0, 0, 0}, {1, 1, 0}, 0.4)},
      {"cone", F::cone({0.1, 0, 0}, {1, 0, 0}, 25)},
      {"box", F::box({-0.5, -0.25, -0.75}, {0.5, 0.25, 0.75})},
      {"quadric", F::quadric({1, 2, 3, 0.5, -0.25, 0.1, 0, 0.2, 0, -1})},
      {"superquadric", F::superquadric({0, 0, 0}, {1, 0.7, 0.5}, 0.6, 1.4)},
      {"torus", F::torus({0, 0, 0.1}, {0, 1, 1}, 0.8, 0.25)},
      {"transformed", F::sphere({0, 0, 0}, 0.5).transformed(
                          Affine::translation({0.2, 0, 0}) * Affine::rotation({0, 0, 1}, 30) *
                          Affine::scaling({1, 0.5, 2}))},
      {"union", F::sphere({0, 0, 0}, 0.5) | F::box({0, 0, 0}, {1, 1, 1})},
      {"intersection", F::sphere({0, 0, 0}, 0.9) & F::plane({0, 0, 0}, {0, 0, 1})},
      {"difference", F::sphere({0, 0, 0}, 0.9) - F::sphere({0.5, 0, 0}, 0.4)},
      {"complement", F::sphere({0, 0, 0}, 0.6).complement()},
      {"offset", F::box({-0.2, -0.2, -0.2}, {0.2, 0.2, 0.2}).offset(0.3)},
      {"icecream", ice_cream_cone()},
  };
}

}  // namespace

TEST(Implicit, PrimitiveValuesAndSigns) {
  // Exact distances at hand-checked points.
  EXPECT_DOUBLE_EQ(F::plane({0, 0, 1}, {0, 0, 2}).value({5, 7, 3}), 2.0);
  EXPECT_DOUBLE_EQ(F::sphere({1, 0, 0}, 1).value({1, 0, 0}), -1.0);
  EXPECT_DOUBLE_EQ(F::sphere({1, 0, 0}, 1).value({4, 4, 0}), 4.0);
  EXPECT_DOUBLE_EQ(F::cylinder({0, 0, 0}, {0, 0, 1}, 1).value({3, 4, 100}), 4.0);
  EXPECT_NEAR(F::cone({0, 0, 0}, {0, 0, 1}, 45).value({1, 0, 1}), 0.0, 1e-15);
  // A point on the axis at height h is h sin(θ) inside.
  EXPECT_NEAR(F::cone({0, 0, 0}, {0, 0, 1}, 30).value({0, 0, -2}), -1.0, 1e-15);
  EXPECT_DOUBLE_EQ(F::box({0, 0, 0}, {2, 2, 2}).value({1, 1, 1}), -1.0);
  EXPECT_DOUBLE_EQ(F::box({0, 0, 0}, {2, 2, 2}).value({5, 6, 1}), 5.0);
  EXPECT_DOUBLE_EQ(F::quadric({1, 1, 1, 0, 0, 0, 0, 0, 0, -1}).value({1, 1, 1}), 2.0);
  EXPECT_NEAR(F::superquadric({0, 0, 0}, {2, 2, 2}, 1, 1).value({3, 0, 0}), 1.0, 1e-14);
  EXPECT_DOUBLE_EQ(F::torus({0, 0, 0}, {0, 0, 1}, 2, 0.5).value({2, 0, 0}), -0.5);
  EXPECT_DOUBLE_EQ(F::torus({0, 0, 0}, {0, 0, 1}, 2, 0.5).value({0, 0, 0}), 1.5);
}

TEST(Implicit, BooleansFollowTheChapter) {
  const F a = F::sphere({0, 0, 0}, 1), b = F::sphere({1, 0, 0}, 1);
  const Vec3 p{0.3, 0.2, 0.1};
  EXPECT_EQ((a | b).value(p), std::min(a.value(p), b.value(p)));         // eq. 1.15
  EXPECT_EQ((a & b).value(p), std::max(a.value(p), b.value(p)));         // eq. 1.16
  EXPECT_EQ((a - b).value(p), std::max(a.value(p), -b.value(p)));        // eq. 1.17
  EXPECT_EQ(F::union_of({a, b, F::plane({0, 0, 0}, {1, 0, 0})}).value(p),
            std::min({a.value(p), b.value(p), p.x}));
}

TEST(Implicit, IceCreamConeRegions) {
  const F ice = ice_cream_cone();
  EXPECT_LT(ice.value({0.6, 0, 0}), 0);        // inside the cone
  EXPECT_GT(ice.value({0.05, 0, 0}), 0);       // clipped off by x = 0.1
  EXPECT_LT(ice.value({1.333, 0, -0.3}), 0);   // in the cream
  EXPECT_GT(ice.value({1.5, 0, 0.45}), 0);     // in the bite
  EXPECT_GT(ice.value({-0.5, 0, 0}), 0);       // the other nappe is clipped
}

TEST(Implicit, AnalyticGradientsMatchFiniteDifferences) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  for (const auto& [name, f] : catalogue()) {
    int checked = 0;
    for (int trial = 0; trial < 400 && checked < 60; ++trial) {
      const Vec3 p{u(rng), u(rng), u(rng)};
      const double h = 1e-6;
      Vec3 fd;
      bool smooth = true;
      for (int a = 0; a < 3; ++a) {
        Vec3 dp{0, 0, 0};
        dp[a] = h;
        const double fp = f.value(p + dp), fm = f.value(p - dp), f0 = f.value(p);
        fd[a] = (fp - fm) / (2 * h);
        // Skip creases (booleans, box edges, axes): one-sided slopes disagree there.
        const double one_sided = (fp - f0) / h - (f0 - fm) / h;
        if (std::abs(one_sided) > 1e-3 * (1 + std::abs(fd[a]))) smooth = false;
      }
      if (!smooth) continue;
      const Vec3 g = f.gradient(p);
      for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(g[a], fd[a], 1e-5 * (1 + std::abs(fd[a]))) << name << " axis " << a;
      }
      ++checked;
    }
    EXPECT_GE(checked, 30) << name << ": too few smooth sample points";
  }
}

TEST(Implicit, DistancePrimitivesHaveUnitGradient) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (const char* name : {"plane", "sphere", "cylinder", "cone", "box", "torus"}) {
    for (const auto& [n, f] : catalogue()) {
      if (n != name) continue;
      for (int i = 0; i < 50; ++i) {
        const Vec3 p{u(rng), u(rng), u(rng)};
        EXPECT_NEAR(norm(f.gradient(p)), 1.0, 1e-12) << name;
      }
    }
  }
}

TEST(Implicit, BatchedEvaluationEqualsPointwiseExactly) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  const std::size_t n = 1000;  // not a multiple of the block size
  std::vector<double> xyz(3 * n), x(n), y(n), z(n), out(n), out2(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = xyz[3 * i] = u(rng);
    y[i] = xyz[3 * i + 1] = u(rng);
    z[i] = xyz[3 * i + 2] = u(rng);
  }
  for (const auto& [name, f] : catalogue()) {
    f.evaluate(xyz, out);
    f.evaluate(x, y, z, out2);
    for (std::size_t i = 0; i < n; ++i) {
      ASSERT_EQ(out[i], f.value({x[i], y[i], z[i]})) << name;
      ASSERT_EQ(out2[i], out[i]) << name;
    }
  }
  EXPECT_THROW(catalogue()[0].second.evaluate(std::span<const double>(xyz.data(), 5), out), Error);
}

TEST(Implicit, BoundsContainEveryValueInTheBox) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.5, 1.5), s(0.01, 0.8), t(0, 1);
  for (const auto& [name, f] : catalogue()) {
    for (int trial = 0; trial < 100; ++trial) {
      Bounds b;
      const Vec3 c{u(rng), u(rng), u(rng)};
      const Vec3 h{s(rng), s(rng), s(rng)};
      b.extend(c - h);
      b.extend(c + h);
      const Interval iv = f.bound(b);
      ASSERT_LE(iv.lo, iv.hi) << name;
      for (int k = 0; k < 50; ++k) {
        const Vec3 p{b.min.x + t(rng) * (b.max.x - b.min.x), b.min.y + t(rng) * (b.max.y - b.min.y),
                     b.min.z + t(rng) * (b.max.z - b.min.z)};
        const double v = f.value(p);
        ASSERT_GE(v, iv.lo) << name << " at trial " << trial;
        ASSERT_LE(v, iv.hi) << name << " at trial " << trial;
      }
    }
  }
}

TEST(Implicit, BoundsAreTightEnoughToCull) {
  // A unit sphere's bound over a far box must exclude zero (or sparse sampling prunes nothing).
  Bounds far;
  far.extend({3, 3, 3});
  far.extend({3.5, 3.5, 3.5});
  for (const auto& [name, f] : catalogue()) {
    if (name == "plane" || name == "cylinder" || name == "cone" || name == "complement" ||
        name == "quadric") {
      continue;  // unbounded surfaces may pass anywhere
    }
    const Interval iv = f.bound(far);
    EXPECT_GT(iv.lo, 0) << name;
  }
}

TEST(Implicit, BadParametersNameTheParameter) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(error_message([] { (void)F::plane({0, 0, 0}, {0, 0, 0}); }).find("'normal' has zero length"), std::string::npos);
  EXPECT_NE(error_message([] { (void)F::sphere({0, 0, 0}, -1); }).find("'r' (radius) is negative"), std::string::npos);
  EXPECT_NE(error_message([&] { (void)F::sphere({nan, 0, 0}, 1); }).find("'center' is not finite"), std::string::npos);
  EXPECT_NE(error_message([] { (void)F::cylinder({0, 0, 0}, {0, 0, 0}, 1); }).find("'axis'"), std::string::npos);
  EXPECT_NE(error_message([] { (void)F::cone({0, 0, 0}, {1, 0, 0}, 90); }).find("(0, 90)"), std::string::npos);
  EXPECT_NE(error_message([] { (void)F::cone({0, 0, 0}, {1, 0, 0}, 0); }).find("'angle'"), std::string::npos);
  EXPECT_NE(error_message([&] { (void)F::cone({0, 0, 0}, {1, 0, 0}, nan); }).find("'angle' is not finite"), std::string::npos);
  EXPECT_NE(error_message([] { (void)F::box({1, 0, 0}, {0, 1, 1}); }).find("'min' exceeds 'max'"), std::string::npos);
  EXPECT_NE(error_message([] { (void)F::quadric({0, 0, 0, 0, 0, 0, 0, 0, 0, 1}); }).find("constant"), std::string::npos);
  EXPECT_NE(error_message([] { (void)F::torus({0, 0, 0}, {0, 0, 1}, 0, 0.1); }).find("'R'"), std::string::npos);
  EXPECT_NE(error_message([] { (void)F::superquadric({0, 0, 0}, {1, 0, 1}, 1, 1); }).find("'radii'"), std::string::npos);
  EXPECT_NE(error_message([] { (void)F::sphere({0, 0, 0}, 1).transformed(Affine::scaling({1, 0, 1})); }).find("singular"),
            std::string::npos);
  EXPECT_THROW((void)F::union_of({}), Error);
}

TEST(Implicit, HugeAndTinyDirectionsAreNormalisedWithoutOverflow) {
  // |(1e308, 1e308, 0)| overflows and |(0, 0, 1e-320)| underflows; both are directions.
  const F a = F::plane({0, 0, 0}, {1e308, 1e308, 0});
  EXPECT_NEAR(a.value({1, 1, 0}), std::sqrt(2.0), 1e-15);
  const F b = F::plane({0, 0, 0}, {0, 0, 1e-320});
  EXPECT_DOUBLE_EQ(b.value({0, 0, 2}), 2.0);
  const F c = F::cylinder({0, 0, 0}, {0, 1e308, 0}, 1);
  EXPECT_DOUBLE_EQ(c.value({0, 5, 0}), -1.0);
}

TEST(Affine, InverseAndComposition) {
  const Affine m = Affine::translation({1, 2, 3}) * Affine::rotation({1, 1, 0}, 40) * Affine::scaling({2, 3, 0.5});
  const Affine inv = m.inverse();
  const Vec3 p{0.3, -0.7, 1.1};
  const Vec3 q = inv.apply(m.apply(p));
  EXPECT_NEAR(q.x, p.x, 1e-14);
  EXPECT_NEAR(q.y, p.y, 1e-14);
  EXPECT_NEAR(q.z, p.z, 1e-14);
  // A translated sphere is the sphere around the translated center.
  const F moved = F::sphere({0, 0, 0}, 1).transformed(Affine::translation({2, 0, 0}));
  EXPECT_DOUBLE_EQ(moved.value({2, 0, 0}), -1.0);
}

TEST(Implicit, CombinationsDeeperThanTheLimitAreRefused) {
  // Every recursive walk of the tree is bounded by kMaxFunctionDepth levels: a factory that would
  // go deeper throws instead of building a function that overflows the stack when evaluated.
  ImplicitFunction f = ImplicitFunction::sphere({0, 0, 0}, 1);
  EXPECT_EQ(f.depth(), 1);
  for (int level = 2; level <= kMaxFunctionDepth; ++level) {
    f = level % 2 ? f.offset(0.0) : f.complement();
    ASSERT_EQ(f.depth(), level);
  }
  EXPECT_EQ(ImplicitFunction::union_of({f}).depth(), kMaxFunctionDepth);  // f itself
  try {
    (void)f.transformed(Affine::translation({1, 0, 0}));
    ADD_FAILURE() << "no Error for 101 levels";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "transform: the function would be nested 101 levels deep; the limit is 100");
  }
  EXPECT_THROW((void)(f | ImplicitFunction::sphere({0, 0, 0}, 2)), Error);
  EXPECT_THROW((void)f.minus(ImplicitFunction::sphere({0, 0, 0}, 2)), Error);
  EXPECT_THROW((void)f.complement(), Error);
}
