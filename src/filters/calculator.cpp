// The array calculator (filters/calculator.hpp): a recursive-descent parser turns the expression
// into a list of nodes, children before parents; evaluation runs the list over blocks of
// kCalcBlock tuples, each node filling its own buffer of 1 or 3 doubles per tuple, so every
// operation is a tight loop over a block (vectorised) rather than a tree walk per tuple.

#include "isoforge/filters/calculator.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <vector>

#include <fmt/format.h>

#include "isoforge/core/parallel.hpp"

namespace isoforge {
namespace {

constexpr std::size_t kCalcBlock = 1024;
constexpr int kCalcMaxDepth = 100;

enum class CalcOp : std::uint8_t {
  Const, Array, Coords, Neg, Add, Sub, Mul, Div, Pow, Func1, Func2, Mag, Unit, Dot, Cross, Vector
};

enum class Func1 : std::uint8_t {
  Abs, Sqrt, Exp, Log, Log10, Sin, Cos, Tan, Asin, Acos, Atan, Sinh, Cosh, Tanh, Floor, Ceil
};
enum class Func2 : std::uint8_t { Min, Max, Atan2, Pow };

constexpr std::array<std::pair<std::string_view, Func1>, 16> kFunc1 = {{
    {"abs", Func1::Abs},   {"sqrt", Func1::Sqrt},   {"exp", Func1::Exp},   {"log", Func1::Log},
    {"log10", Func1::Log10}, {"sin", Func1::Sin},   {"cos", Func1::Cos},   {"tan", Func1::Tan},
    {"asin", Func1::Asin}, {"acos", Func1::Acos},   {"atan", Func1::Atan}, {"sinh", Func1::Sinh},
    {"cosh", Func1::Cosh}, {"tanh", Func1::Tanh},   {"floor", Func1::Floor}, {"ceil", Func1::Ceil},
}};
constexpr std::array<std::pair<std::string_view, Func2>, 4> kFunc2 = {{
    {"min", Func2::Min}, {"max", Func2::Max}, {"atan2", Func2::Atan2}, {"pow", Func2::Pow},
}};

/// One operation: its operands are earlier nodes (a, b, c), its result `width` (1 or 3)
/// doubles per tuple.
struct CalcNode {
  CalcOp op = CalcOp::Const;
  int width = 1;
  int a = -1, b = -1, c = -1;
  double value = 0;                 // Const
  const DataArray* array = nullptr;  // Array: components [component, component + width)
  int component = 0;                // Array; Coords: the axis when width is 1
  std::uint8_t func = 0;            // Func1, Func2
};

class CalcParser {
 public:
  CalcParser(std::string_view text, const Attributes& arrays, bool cells)
      : text_(text), arrays_(arrays), cells_(cells) {}

  std::vector<CalcNode> parse() {
    skip_space();
    if (pos_ >= text_.size()) fail(pos_, "the expression is empty");
    (void)expression();  // the last node is the result
    skip_space();
    if (pos_ < text_.size()) fail(pos_, fmt::format("unexpected '{}'", text_[pos_]));
    return std::move(nodes_);
  }

 private:
  [[noreturn]] void fail(std::size_t at, const std::string& what) const {
    throw Error(fmt::format("calculator: column {}: {}", at + 1, what));
  }
  void skip_space() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  bool accept(char c) {
    skip_space();
    if (pos_ < text_.size() && text_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  void expect(char c, const char* where) {
    if (!accept(c)) {
      fail(pos_, pos_ < text_.size() ? fmt::format("expected '{}' {}, got '{}'", c, where, text_[pos_])
                                     : fmt::format("expected '{}' {} at the end", c, where));
    }
  }
  int push(CalcNode n) {
    nodes_.push_back(n);
    return static_cast<int>(nodes_.size()) - 1;
  }
  int width(int n) const { return nodes_[static_cast<std::size_t>(n)].width; }
  void need(int n, int w, std::size_t at, const char* what) const {
    if (width(n) != w) {
      fail(at, fmt::format("{} needs a {}, got a {}", what, w == 1 ? "scalar" : "vector",
                           width(n) == 1 ? "scalar" : "vector"));
    }
  }
  void enter(std::size_t at) {
    if (++depth_ > kCalcMaxDepth) fail(at, "nested more than 100 levels deep (the limit)");
  }

  int expression() {
    const std::size_t at = pos_;
    enter(at);
    int left = term();
    for (;;) {
      skip_space();
      const std::size_t op_at = pos_;
      const bool add = accept('+');
      if (!add && !accept('-')) break;
      const int right = term();
      if (width(left) != width(right)) {
        fail(op_at, fmt::format("cannot {} a {} and a {}", add ? "add" : "subtract",
                                width(left) == 1 ? "scalar" : "vector",
                                width(right) == 1 ? "scalar" : "vector"));
      }
      left = push({add ? CalcOp::Add : CalcOp::Sub, width(left), left, right});
    }
    --depth_;
    return left;
  }
  int term() {
    int left = unary();
    for (;;) {
      skip_space();
      const std::size_t op_at = pos_;
      const bool mul = accept('*');
      if (!mul && !accept('/')) break;
      const int right = unary();
      if (width(right) == 3 && (!mul || width(left) == 3)) {
        fail(op_at, mul ? "cannot multiply two vectors: use dot() or cross()"
                        : "cannot divide by a vector");
      }
      // Scalar × vector is stored as vector × scalar.
      const bool swap = mul && width(left) == 1 && width(right) == 3;
      left = push({mul ? CalcOp::Mul : CalcOp::Div, std::max(width(left), width(right)),
                   swap ? right : left, swap ? left : right});
    }
    return left;
  }
  int unary() {
    skip_space();
    const std::size_t at = pos_;
    if (accept('-')) {
      enter(at);
      const int operand = unary();
      --depth_;
      return push({CalcOp::Neg, width(operand), operand});
    }
    if (accept('+')) {
      enter(at);
      const int operand = unary();
      --depth_;
      return operand;
    }
    const int base = postfix();
    skip_space();
    const std::size_t op_at = pos_;
    if (accept('^')) {
      enter(op_at);
      const int exponent = unary();
      --depth_;
      need(base, 1, op_at, "'^'");
      need(exponent, 1, op_at, "'^'");
      return push({CalcOp::Pow, 1, base, exponent});
    }
    return base;
  }
  int postfix() {
    int n = primary();
    for (;;) {
      skip_space();
      const std::size_t at = pos_;
      if (!accept('[')) break;
      // Component access: of an array, coords or a vector expression.
      skip_space();
      std::size_t k = 0;
      const auto [end, ec] = std::from_chars(text_.data() + pos_, text_.data() + text_.size(), k);
      if (ec != std::errc()) fail(pos_, "expected a component number after '['");
      pos_ = static_cast<std::size_t>(end - text_.data());
      expect(']', "after the component number");
      CalcNode& node = nodes_[static_cast<std::size_t>(n)];
      const int available = node.op == CalcOp::Array && node.width == 0
                                ? node.array->components()
                                : node.width;
      if (available == 1) fail(at, "a scalar has no components");
      if (k >= static_cast<std::size_t>(available)) {
        fail(at, fmt::format("component {} of {} components (they count from 0)", k, available));
      }
      if (node.op == CalcOp::Array && (node.width == 0 || node.width == 3)) {
        node.component += static_cast<int>(k);
        node.width = 1;
      } else if (node.op == CalcOp::Coords && node.width == 3) {
        node.component = static_cast<int>(k);
        node.width = 1;
      } else {
        // A component of a computed vector: dot with a unit axis.
        CalcNode axis{CalcOp::Vector, 3};
        axis.a = push({CalcOp::Const, 1, -1, -1, -1, k == 0 ? 1.0 : 0.0});
        axis.b = push({CalcOp::Const, 1, -1, -1, -1, k == 1 ? 1.0 : 0.0});
        axis.c = push({CalcOp::Const, 1, -1, -1, -1, k == 2 ? 1.0 : 0.0});
        n = push({CalcOp::Dot, 1, n, push(axis)});
      }
    }
    CalcNode& node = nodes_[static_cast<std::size_t>(n)];
    if (node.op == CalcOp::Array && node.width == 0) {
      fail(column_of_[static_cast<std::size_t>(n)],
           fmt::format("array '{}' has {} components: use '{}[i]' for one of them",
                       node.array->name(), node.array->components(), node.array->name()));
    }
    return n;
  }
  int number() {
    double v = 0;
    const auto [end, ec] = std::from_chars(text_.data() + pos_, text_.data() + text_.size(), v);
    if (ec != std::errc() || !std::isfinite(v)) fail(pos_, "not a finite number");
    pos_ = static_cast<std::size_t>(end - text_.data());
    return push({CalcOp::Const, 1, -1, -1, -1, v});
  }
  int array_node(const std::string& name, std::size_t at) {
    const DataArray* a = arrays_.find(name);
    if (!a) {
      fail(at, fmt::format("no {} array '{}' ({} arrays: {})", cells_ ? "cell" : "point", name,
                           cells_ ? "cell" : "point", arrays_.names()));
    }
    CalcNode n{CalcOp::Array, a->components() == 1 || a->components() == 3 ? a->components() : 0};
    n.array = a;
    const int id = push(n);
    column_of_.resize(nodes_.size(), 0);
    column_of_[static_cast<std::size_t>(id)] = at;
    return id;
  }
  int primary() {
    skip_space();
    const std::size_t at = pos_;
    if (at >= text_.size()) fail(at, "expected a value at the end");
    const char ch = text_[at];
    if (std::isdigit(static_cast<unsigned char>(ch)) || ch == '.') return number();
    if (accept('(')) {
      const int inner = expression();
      expect(')', "to close '('");
      return inner;
    }
    if (accept('[')) {
      int parts[3];
      for (int k = 0; k < 3; ++k) {
        if (k > 0) expect(',', "between a vector's values");
        const std::size_t part_at = pos_;
        parts[k] = expression();
        need(parts[k], 1, part_at, "a vector's value");
      }
      expect(']', "after a vector's three values");
      CalcNode v{CalcOp::Vector, 3, parts[0], parts[1]};
      v.c = parts[2];
      return push(v);
    }
    if (ch == '"') {
      const std::size_t close = text_.find('"', at + 1);
      if (close == std::string_view::npos) fail(at, "unterminated quoted array name");
      pos_ = close + 1;
      return array_node(std::string(text_.substr(at + 1, close - at - 1)), at);
    }
    if (!(std::isalpha(static_cast<unsigned char>(ch)) || ch == '_')) {
      fail(at, fmt::format("unexpected '{}'", ch));
    }
    while (pos_ < text_.size() &&
           (std::isalnum(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '_')) {
      ++pos_;
    }
    const std::string word(text_.substr(at, pos_ - at));
    skip_space();
    if (pos_ < text_.size() && text_[pos_] == '(' && !arrays_.has(word)) return call(word, at);
    if (arrays_.has(word)) return array_node(word, at);
    if (word == "pi") return push({CalcOp::Const, 1, -1, -1, -1, std::numbers::pi});
    if (word == "coords" || word == "coordsX" || word == "coordsY" || word == "coordsZ") {
      if (cells_) fail(at, "coords are point coordinates: not available over cells");
      CalcNode n{CalcOp::Coords, word == "coords" ? 3 : 1};
      n.component = word == "coords" ? 0 : word.back() - 'X';
      return push(n);
    }
    return array_node(word, at);  // fails, listing the arrays there are
  }
  int call(const std::string& name, std::size_t at) {
    expect('(', "after a function name");
    enter(at);
    std::vector<int> args;
    std::vector<std::size_t> arg_at;
    skip_space();
    if (!accept(')')) {
      do {
        skip_space();
        arg_at.push_back(pos_);
        args.push_back(expression());
      } while (accept(','));
      expect(')', fmt::format("to close {}(", name).c_str());
    }
    --depth_;
    auto arity = [&](std::size_t n) {
      if (args.size() != n) {
        fail(at, fmt::format("{}() takes {} argument{}, got {}", name, n, n == 1 ? "" : "s",
                             args.size()));
      }
    };
    for (const auto& [fname, f] : kFunc1) {
      if (name == fname) {
        arity(1);
        need(args[0], 1, arg_at[0], (name + "()").c_str());
        CalcNode n{CalcOp::Func1, 1, args[0]};
        n.func = static_cast<std::uint8_t>(f);
        return push(n);
      }
    }
    for (const auto& [fname, f] : kFunc2) {
      if (name == fname) {
        arity(2);
        need(args[0], 1, arg_at[0], (name + "()").c_str());
        need(args[1], 1, arg_at[1], (name + "()").c_str());
        CalcNode n{CalcOp::Func2, 1, args[0], args[1]};
        n.func = static_cast<std::uint8_t>(f);
        return push(n);
      }
    }
    if (name == "mag" || name == "norm") {
      arity(1);
      need(args[0], 3, arg_at[0], (name + "()").c_str());
      return push({name == "mag" ? CalcOp::Mag : CalcOp::Unit, name == "mag" ? 1 : 3, args[0]});
    }
    if (name == "dot" || name == "cross") {
      arity(2);
      need(args[0], 3, arg_at[0], (name + "()").c_str());
      need(args[1], 3, arg_at[1], (name + "()").c_str());
      return push({name == "dot" ? CalcOp::Dot : CalcOp::Cross, name == "dot" ? 1 : 3, args[0],
                   args[1]});
    }
    fail(at, fmt::format("unknown function '{}'", name));
  }

  std::string_view text_;
  const Attributes& arrays_;
  bool cells_;
  std::size_t pos_ = 0;
  int depth_ = 0;
  std::vector<CalcNode> nodes_;
  std::vector<std::size_t> column_of_;
};

double apply(Func1 f, double x) {
  switch (f) {
    case Func1::Abs: return std::abs(x);
    case Func1::Sqrt: return std::sqrt(x);
    case Func1::Exp: return std::exp(x);
    case Func1::Log: return std::log(x);
    case Func1::Log10: return std::log10(x);
    case Func1::Sin: return std::sin(x);
    case Func1::Cos: return std::cos(x);
    case Func1::Tan: return std::tan(x);
    case Func1::Asin: return std::asin(x);
    case Func1::Acos: return std::acos(x);
    case Func1::Atan: return std::atan(x);
    case Func1::Sinh: return std::sinh(x);
    case Func1::Cosh: return std::cosh(x);
    case Func1::Tanh: return std::tanh(x);
    case Func1::Floor: return std::floor(x);
    case Func1::Ceil: return std::ceil(x);
  }
  return x;
}

double apply(Func2 f, double x, double y) {
  switch (f) {
    case Func2::Min: return std::min(x, y);
    case Func2::Max: return std::max(x, y);
    case Func2::Atan2: return std::atan2(x, y);
    case Func2::Pow: return std::pow(x, y);
  }
  return x;
}

/// Tuples [first, first + n) of components [c0, c0 + w) of `a`, as doubles, w per tuple.
void load_tuples(const DataArray& a, int c0, int w, std::size_t first, std::size_t n, double* out) {
  const auto comps = static_cast<std::size_t>(a.components());
  const auto width = static_cast<std::size_t>(w);
  a.visit([&](const auto& values) {
    const auto* v = values.data() + first * comps + static_cast<std::size_t>(c0);
    if (width == comps) {  // whole tuples: one contiguous run (vectorised conversion)
      for (std::size_t i = 0; i < n * comps; ++i) out[i] = static_cast<double>(v[i]);
    } else if (width == 1) {
      for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<double>(v[i * comps]);
    } else {
      for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t k = 0; k < width; ++k) out[i * width + k] = static_cast<double>(v[i * comps + k]);
      }
    }
  });
}

/// r = a op b over n tuples of width w, b a scalar per tuple (`scalar_b`) or of width w: the
/// loops spelt out per case so that each vectorises.
template <class Op>
void scale_tuples(double* r, const double* a, const double* b, std::size_t n, std::size_t w,
                  bool scalar_b, Op op) {
  if (!scalar_b || w == 1) {
    for (std::size_t i = 0; i < n * w; ++i) r[i] = op(a[i], b[i]);
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      const double y = b[i];
      for (std::size_t k = 0; k < w; ++k) r[w * i + k] = op(a[w * i + k], y);
    }
  }
}

/// Evaluates the nodes over tuples [first, first + n) into per-node buffers.
void evaluate_block(const std::vector<CalcNode>& nodes, DatasetRef input, std::size_t first,
                    std::size_t n, std::vector<std::vector<double>>& buf) {
  for (std::size_t id = 0; id < nodes.size(); ++id) {
    const CalcNode& node = nodes[id];
    double* r = buf[id].data();
    const double* a = node.a >= 0 ? buf[static_cast<std::size_t>(node.a)].data() : nullptr;
    const double* b = node.b >= 0 ? buf[static_cast<std::size_t>(node.b)].data() : nullptr;
    const double* c = node.c >= 0 ? buf[static_cast<std::size_t>(node.c)].data() : nullptr;
    const std::size_t m = n * static_cast<std::size_t>(node.width);
    switch (node.op) {
      case CalcOp::Const:
        std::fill(r, r + n, node.value);
        break;
      case CalcOp::Array:
        load_tuples(*node.array, node.component, node.width, first, n, r);
        break;
      case CalcOp::Coords:
        for (std::size_t i = 0; i < n; ++i) {
          const Vec3 p = point(input, static_cast<Index>(first + i));
          if (node.width == 3) {
            r[3 * i] = p.x, r[3 * i + 1] = p.y, r[3 * i + 2] = p.z;
          } else {
            r[i] = p[node.component];
          }
        }
        break;
      case CalcOp::Neg:
        for (std::size_t i = 0; i < m; ++i) r[i] = -a[i];
        break;
      case CalcOp::Add:
        for (std::size_t i = 0; i < m; ++i) r[i] = a[i] + b[i];
        break;
      case CalcOp::Sub:
        for (std::size_t i = 0; i < m; ++i) r[i] = a[i] - b[i];
        break;
      case CalcOp::Mul:
      case CalcOp::Div: {
        const CalcNode& right = nodes[static_cast<std::size_t>(node.b)];
        const bool scalar_b = right.width == 1;
        const auto w = static_cast<std::size_t>(node.width);
        if (right.op == CalcOp::Const) {  // by a constant: no buffer to read
          const double y = right.value;
          if (node.op == CalcOp::Mul) {
            for (std::size_t i = 0; i < m; ++i) r[i] = a[i] * y;
          } else {
            for (std::size_t i = 0; i < m; ++i) r[i] = a[i] / y;
          }
        } else if (node.op == CalcOp::Mul) {
          scale_tuples(r, a, b, n, w, scalar_b, [](double x, double y) { return x * y; });
        } else {
          scale_tuples(r, a, b, n, w, scalar_b, [](double x, double y) { return x / y; });
        }
        break;
      }
      case CalcOp::Pow:
        for (std::size_t i = 0; i < n; ++i) r[i] = std::pow(a[i], b[i]);
        break;
      case CalcOp::Func1: {
        const auto f = static_cast<Func1>(node.func);
        for (std::size_t i = 0; i < n; ++i) r[i] = apply(f, a[i]);
        break;
      }
      case CalcOp::Func2: {
        const auto f = static_cast<Func2>(node.func);
        for (std::size_t i = 0; i < n; ++i) r[i] = apply(f, a[i], b[i]);
        break;
      }
      case CalcOp::Mag:
        for (std::size_t i = 0; i < n; ++i) {
          r[i] = std::sqrt(a[3 * i] * a[3 * i] + a[3 * i + 1] * a[3 * i + 1] + a[3 * i + 2] * a[3 * i + 2]);
        }
        break;
      case CalcOp::Unit:
        for (std::size_t i = 0; i < n; ++i) {
          const double l = std::sqrt(a[3 * i] * a[3 * i] + a[3 * i + 1] * a[3 * i + 1] +
                                     a[3 * i + 2] * a[3 * i + 2]);
          for (int k = 0; k < 3; ++k) r[3 * i + static_cast<std::size_t>(k)] = a[3 * i + static_cast<std::size_t>(k)] / l;
        }
        break;
      case CalcOp::Dot:
        for (std::size_t i = 0; i < n; ++i) {
          r[i] = a[3 * i] * b[3 * i] + a[3 * i + 1] * b[3 * i + 1] + a[3 * i + 2] * b[3 * i + 2];
        }
        break;
      case CalcOp::Cross:
        for (std::size_t i = 0; i < n; ++i) {
          const double* u = a + 3 * i;
          const double* v = b + 3 * i;
          r[3 * i] = u[1] * v[2] - u[2] * v[1];
          r[3 * i + 1] = u[2] * v[0] - u[0] * v[2];
          r[3 * i + 2] = u[0] * v[1] - u[1] * v[0];
        }
        break;
      case CalcOp::Vector:
        for (std::size_t i = 0; i < n; ++i) {
          r[3 * i] = a[i], r[3 * i + 1] = b[i], r[3 * i + 2] = c[i];
        }
        break;
    }
  }
}

}  // namespace

DataArray calculate(DatasetRef input, const std::string& name, std::string_view expression,
                    const CalculatorOptions& o) {
  if (name.empty()) throw Error("calculator: the result array needs a name");
  if (o.type != ScalarType::Float32 && o.type != ScalarType::Float64) {
    throw Error("calculator: the result type must be Float32 or Float64");
  }
  validate(input);
  const Attributes& arrays = o.cells ? cell_data(input) : point_data(input);
  const std::vector<CalcNode> nodes = CalcParser(expression, arrays, o.cells).parse();
  const std::size_t n = o.cells ? num_cells(input) : num_points(input);
  const int width = nodes.back().width;
  DataArray out = DataArray::uninitialized(name, o.type, width, n);
  const std::size_t blocks = (n + kCalcBlock - 1) / kCalcBlock;
  parallel_for_range(
      blocks, 4,
      [&](std::size_t b0, std::size_t b1) {
        std::vector<std::vector<double>> buf(nodes.size());
        for (std::size_t i = 0; i < nodes.size(); ++i) {
          buf[i].resize(kCalcBlock * static_cast<std::size_t>(nodes[i].width));
        }
        for (std::size_t b = b0; b < b1; ++b) {
          const std::size_t first = b * kCalcBlock, count = std::min(kCalcBlock, n - first);
          evaluate_block(nodes, input, first, count, buf);
          const double* r = buf.back().data();
          const std::size_t m = count * static_cast<std::size_t>(width);
          out.visit([&](auto& values) {
            using T = typename std::decay_t<decltype(values)>::value_type;
            if constexpr (std::is_floating_point_v<T>) {
              T* dst = values.data() + first * static_cast<std::size_t>(width);
              for (std::size_t i = 0; i < m; ++i) dst[i] = static_cast<T>(r[i]);
            }
          });
        }
      },
      o.progress, "calculator");
  return out;
}

}  // namespace isoforge
