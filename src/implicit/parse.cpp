// Parser and printer of the implicit-function expression language (docs/implicit.md).
//
//   expr   := NAME '(' [arg (',' arg)*] ')'
//   arg    := NAME '=' value | value
//   value  := expr | NUMBER | '[' NUMBER (',' NUMBER)* ']'
//
// Printing uses the shortest decimal form that reads back to the same double, so
// parse_implicit(f.to_string()) evaluates bit-identically to f.

#include "isoforge/implicit/parse.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "function_node.hpp"
#include "isoforge/core/error.hpp"

namespace isoforge {

namespace {

using FunctionKind = ImplicitFunction::Kind;

// A parsed argument value.
struct Value {
  std::variant<double, std::vector<double>, ImplicitFunction> v;
};

struct Call {
  std::string name;
  std::size_t column = 0;
  std::vector<Value> positional;
  std::map<std::string, Value> named;
};

class Parser {
 public:
  explicit Parser(std::string_view s) : s_(s) {}

  ImplicitFunction parse_all() {
    ImplicitFunction f = expr();
    skip();
    if (pos_ != s_.size()) fail("unexpected '" + std::string(1, s_[pos_]) + "' after the expression");
    return f;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error("function expression: column " + std::to_string(pos_ + 1) + ": " + what);
  }
  void skip() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  bool accept(char c) {
    skip();
    if (pos_ < s_.size() && s_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  void expect(char c) {
    if (!accept(c)) {
      fail(std::string("expected '") + c + "'" +
           (pos_ < s_.size() ? ", found '" + std::string(1, s_[pos_]) + "'" : " at the end"));
    }
  }
  std::string name() {
    skip();
    const std::size_t start = pos_;
    while (pos_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_')) ++pos_;
    if (start == pos_) fail("expected a name");
    return std::string(s_.substr(start, pos_ - start));
  }
  double number() {
    skip();
    const char* b = s_.data() + pos_;
    const char* e = s_.data() + s_.size();
    if (b != e && *b == '+') ++b;
    double v = 0;
    auto [p, ec] = std::from_chars(b, e, v);
    if (ec != std::errc() || !std::isfinite(v)) fail("expected a finite number");
    pos_ = static_cast<std::size_t>(p - s_.data());
    return v;
  }
  bool at_number() {
    skip();
    if (pos_ >= s_.size()) return false;
    const char c = s_[pos_];
    return std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '+' || c == '.';
  }
  Value value() {
    skip();
    if (accept('[')) {
      std::vector<double> v;
      if (!accept(']')) {
        do v.push_back(number());
        while (accept(','));
        expect(']');
      }
      return {v};
    }
    if (at_number()) return {number()};
    return {expr()};
  }
  ImplicitFunction expr() {
    skip();
    Call call;
    call.column = pos_ + 1;
    call.name = name();
    // Parsing recurses once per level too: refuse before going deeper than a function may be.
    if (depth_ == kMaxFunctionDepth) {
      throw Error("function expression: column " + std::to_string(call.column) + ": " + call.name +
                  ": nested more than " + std::to_string(kMaxFunctionDepth) +
                  " levels deep (the limit)");
    }
    struct Level {
      int& depth;
      explicit Level(int& d) : depth(++d) {}
      ~Level() { --depth; }
    } level(depth_);
    expect('(');
    if (!accept(')')) {
      do {
        skip();
        // NAME '=' value, or a positional value.
        const std::size_t save = pos_;
        if (pos_ < s_.size() && std::isalpha(static_cast<unsigned char>(s_[pos_]))) {
          std::string key = name();
          if (accept('=')) {
            if (call.named.count(key)) fail("parameter '" + key + "' given twice");
            call.named[key] = value();
            continue;
          }
          pos_ = save;
        }
        call.positional.push_back(value());
      } while (accept(','));
      expect(')');
    }
    return build(call);
  }

  // ---- argument access ----
  [[noreturn]] void fail_call(const Call& c, const std::string& what) const {
    throw Error("function expression: column " + std::to_string(c.column) + ": " + c.name + ": " + what);
  }
  const Value* named(Call& c, std::initializer_list<const char*> keys) {
    for (const char* k : keys) {
      auto it = c.named.find(k);
      if (it != c.named.end()) {
        used_.push_back(k);
        return &it->second;
      }
    }
    return nullptr;
  }
  double num(Call& c, std::initializer_list<const char*> keys, std::optional<double> def) {
    const Value* v = named(c, keys);
    if (!v) {
      if (!def) fail_call(c, std::string("missing parameter '") + *keys.begin() + "'");
      return *def;
    }
    if (const double* d = std::get_if<double>(&v->v)) return *d;
    fail_call(c, std::string("parameter '") + *keys.begin() + "' must be a number");
  }
  Vec3 vec(Call& c, std::initializer_list<const char*> keys, std::optional<Vec3> def) {
    const Value* v = named(c, keys);
    if (!v) {
      if (!def) fail_call(c, std::string("missing parameter '") + *keys.begin() + "'");
      return *def;
    }
    if (const auto* a = std::get_if<std::vector<double>>(&v->v); a && a->size() == 3) {
      return {(*a)[0], (*a)[1], (*a)[2]};
    }
    if (const double* d = std::get_if<double>(&v->v)) return {*d, *d, *d};
    fail_call(c, std::string("parameter '") + *keys.begin() + "' must be [x, y, z]");
  }
  ImplicitFunction fn(const Call& c, const Value& v) {
    if (const auto* f = std::get_if<ImplicitFunction>(&v.v)) return *f;
    fail_call(c, "expected a function argument");
  }
  void finish(const Call& c) {
    for (const auto& [k, v] : c.named) {
      if (std::find(used_.begin(), used_.end(), k) == used_.end()) {
        fail_call(c, "unknown parameter '" + k + "'");
      }
    }
  }
  void no_positional(const Call& c) {
    if (!c.positional.empty()) fail_call(c, "takes named parameters only (e.g. r=1)");
  }

  ImplicitFunction build(Call& c) {
    used_.clear();
    using F = ImplicitFunction;
    const std::string& n = c.name;
    std::optional<F> out;
    if (n == "plane") {
      no_positional(c);
      out = F::plane(vec(c, {"origin", "point"}, Vec3{0, 0, 0}), vec(c, {"normal"}, Vec3{0, 0, 1}));
    } else if (n == "sphere") {
      no_positional(c);
      out = F::sphere(vec(c, {"center"}, Vec3{0, 0, 0}), num(c, {"r", "radius"}, 1.0));
    } else if (n == "cylinder") {
      no_positional(c);
      out = F::cylinder(vec(c, {"point", "center"}, Vec3{0, 0, 0}), vec(c, {"axis"}, Vec3{0, 0, 1}),
                        num(c, {"r", "radius"}, 1.0));
    } else if (n == "cone") {
      no_positional(c);
      out = F::cone(vec(c, {"apex"}, Vec3{0, 0, 0}), vec(c, {"axis"}, Vec3{0, 0, 1}),
                    num(c, {"angle"}, 45.0));
    } else if (n == "box") {
      no_positional(c);
      out = F::box(vec(c, {"min"}, Vec3{-1, -1, -1}), vec(c, {"max"}, Vec3{1, 1, 1}));
    } else if (n == "quadric") {
      no_positional(c);
      const Value* v = named(c, {"a", "coefficients"});
      const auto* a = v ? std::get_if<std::vector<double>>(&v->v) : nullptr;
      if (!a || a->size() != 10) fail_call(c, "parameter 'a' must be a list of 10 coefficients");
      std::array<double, 10> coeffs{};
      std::copy(a->begin(), a->end(), coeffs.begin());
      out = F::quadric(coeffs);
    } else if (n == "superquadric") {
      no_positional(c);
      out = F::superquadric(vec(c, {"center"}, Vec3{0, 0, 0}), vec(c, {"radii"}, Vec3{1, 1, 1}),
                            num(c, {"n"}, 1.0), num(c, {"e"}, 1.0));
    } else if (n == "torus") {
      no_positional(c);
      out = F::torus(vec(c, {"center"}, Vec3{0, 0, 0}), vec(c, {"axis"}, Vec3{0, 0, 1}),
                     num(c, {"R", "major"}, 1.0), num(c, {"r", "minor"}, 0.25));
    } else if (n == "union" || n == "intersection") {
      if (c.positional.empty()) fail_call(c, "needs at least one function");
      std::vector<F> parts;
      for (const auto& v : c.positional) parts.push_back(fn(c, v));
      out = n == "union" ? F::union_of(std::move(parts)) : F::intersection_of(std::move(parts));
    } else if (n == "difference") {
      if (c.positional.size() != 2) fail_call(c, "needs exactly two functions");
      out = fn(c, c.positional[0]).minus(fn(c, c.positional[1]));
    } else if (n == "complement") {
      if (c.positional.size() != 1) fail_call(c, "needs exactly one function");
      out = fn(c, c.positional[0]).complement();
    } else if (n == "offset") {
      if (c.positional.empty()) fail_call(c, "needs a function");
      double d = 0;
      if (c.positional.size() == 2) {
        const double* v = std::get_if<double>(&c.positional[1].v);
        if (!v) fail_call(c, "the distance must be a number");
        d = *v;
      } else {
        d = num(c, {"d", "distance"}, std::nullopt);
      }
      out = fn(c, c.positional[0]).offset(d);
    } else if (n == "translate" || n == "scale") {
      if (c.positional.empty() || c.positional.size() > 2) fail_call(c, "needs a function and a vector");
      Vec3 v;
      if (c.positional.size() == 2) {
        const Value& a = c.positional[1];
        if (const auto* l = std::get_if<std::vector<double>>(&a.v); l && l->size() == 3) {
          v = {(*l)[0], (*l)[1], (*l)[2]};
        } else if (const double* d = std::get_if<double>(&a.v); d && n == "scale") {
          v = {*d, *d, *d};
        } else {
          fail_call(c, "the second argument must be [x, y, z]");
        }
      } else {
        v = vec(c, {"by"}, std::nullopt);
      }
      out = fn(c, c.positional[0]).transformed(n == "translate" ? Affine::translation(v) : Affine::scaling(v));
    } else if (n == "rotate") {
      if (c.positional.size() != 1) fail_call(c, "needs a function (and axis=, angle=)");
      out = fn(c, c.positional[0]).transformed(Affine::rotation(vec(c, {"axis"}, Vec3{0, 0, 1}),
                                                                num(c, {"angle"}, std::nullopt)));
    } else if (n == "transform") {
      if (c.positional.size() != 1) fail_call(c, "needs a function (and matrix=, translation=)");
      const Value* m = named(c, {"matrix"});
      const auto* a = m ? std::get_if<std::vector<double>>(&m->v) : nullptr;
      if (!a || a->size() != 9) fail_call(c, "parameter 'matrix' must be 9 numbers, row-major");
      Affine af;
      std::copy(a->begin(), a->end(), af.a.begin());
      af.t = vec(c, {"translation"}, Vec3{0, 0, 0});
      out = fn(c, c.positional[0]).transformed(af);
    } else if (n == "icecream") {
      no_positional(c);
      out = ice_cream_cone();
    } else {
      fail_call(c, "unknown function (known: plane sphere cylinder cone box quadric superquadric "
                   "torus union intersection difference complement offset translate scale rotate "
                   "transform icecream)");
    }
    finish(c);
    return *out;
  }

  std::string_view s_;
  std::size_t pos_ = 0;
  int depth_ = 0;  ///< functions being parsed around the current position
  std::vector<std::string> used_;
};

std::string num_str(double v) {
  char buf[32];
  auto [p, ec] = std::to_chars(buf, buf + sizeof(buf), v);
  return std::string(buf, p);
}

std::string vec_str(double a, double b, double c) {
  return "[" + num_str(a) + ", " + num_str(b) + ", " + num_str(c) + "]";
}

std::string print(const ImplicitFunction::Node& n) {
  const auto& p = n.p;
  const Vec3& d = n.direction;  // as given: parsing normalizes it exactly as the first time
  auto children = [&](const char* name) {
    std::string s = std::string(name) + "(";
    for (std::size_t i = 0; i < n.children.size(); ++i) {
      if (i) s += ", ";
      s += print(n.children[i].node());
    }
    return s + ")";
  };
  switch (n.kind) {
    case FunctionKind::Plane:
      return "plane(origin=" + vec_str(p[0], p[1], p[2]) + ", normal=" + vec_str(d.x, d.y, d.z) + ")";
    case FunctionKind::Sphere: return "sphere(center=" + vec_str(p[0], p[1], p[2]) + ", r=" + num_str(p[3]) + ")";
    case FunctionKind::Cylinder:
      return "cylinder(point=" + vec_str(p[0], p[1], p[2]) + ", axis=" + vec_str(d.x, d.y, d.z) +
             ", r=" + num_str(p[6]) + ")";
    case FunctionKind::Cone:
      return "cone(apex=" + vec_str(p[0], p[1], p[2]) + ", axis=" + vec_str(d.x, d.y, d.z) +
             ", angle=" + num_str(p[8]) + ")";
    case FunctionKind::Box: return "box(min=" + vec_str(p[0], p[1], p[2]) + ", max=" + vec_str(p[3], p[4], p[5]) + ")";
    case FunctionKind::Quadric: {
      std::string s = "quadric(a=[";
      for (int i = 0; i < 10; ++i) s += (i ? ", " : "") + num_str(p[static_cast<std::size_t>(i)]);
      return s + "])";
    }
    case FunctionKind::Superquadric:
      return "superquadric(center=" + vec_str(p[0], p[1], p[2]) + ", radii=" + vec_str(p[3], p[4], p[5]) +
             ", n=" + num_str(p[6]) + ", e=" + num_str(p[7]) + ")";
    case FunctionKind::Torus:
      return "torus(center=" + vec_str(p[0], p[1], p[2]) + ", axis=" + vec_str(d.x, d.y, d.z) +
             ", R=" + num_str(p[6]) + ", r=" + num_str(p[7]) + ")";
    case FunctionKind::Transform: {
      const auto& a = n.forward.a;
      std::string s = "transform(" + print(n.children[0].node()) + ", matrix=[";
      for (int i = 0; i < 9; ++i) s += (i ? ", " : "") + num_str(a[static_cast<std::size_t>(i)]);
      return s + "], translation=" + vec_str(n.forward.t.x, n.forward.t.y, n.forward.t.z) + ")";
    }
    case FunctionKind::Union: return children("union");
    case FunctionKind::Intersection: return children("intersection");
    case FunctionKind::Difference: return children("difference");
    case FunctionKind::Complement: return children("complement");
    case FunctionKind::Offset: return "offset(" + print(n.children[0].node()) + ", d=" + num_str(p[0]) + ")";
  }
  return "?";
}

}  // namespace

ImplicitFunction parse_implicit(std::string_view expression) { return Parser(expression).parse_all(); }

std::string ImplicitFunction::to_string() const { return print(*node_); }

}  // namespace isoforge
