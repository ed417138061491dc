// isoforge fit: fit a plane, sphere, cylinder, cone or quadric to the points of a dataset and
// print it as a function of the expression language (docs/implicit.md).

#include <fmt/core.h>

#include <map>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/fit/fit_primitive.hpp"
#include "isoforge/io/atomic_file.hpp"
#include "isoforge/io/io.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

namespace {

// The meaning of each parameter, per kind (the layout of FittedPrimitive::parameters).
std::string parameters_text(const FittedPrimitive& f) {
  const auto& p = f.parameters;
  switch (f.kind) {
    case PrimitiveKind::Plane:
      return fmt::format("normal: {:.9g} {:.9g} {:.9g}\noffset: {:.9g}   (n·x = offset)\n", p[0],
                         p[1], p[2], p[3]);
    case PrimitiveKind::Sphere:
      return fmt::format("center: {:.9g} {:.9g} {:.9g}\nradius: {:.9g}\n", p[0], p[1], p[2], p[3]);
    case PrimitiveKind::Cylinder:
      return fmt::format(
          "axis point: {:.9g} {:.9g} {:.9g}\naxis: {:.9g} {:.9g} {:.9g}\nradius: {:.9g}\n", p[0],
          p[1], p[2], p[3], p[4], p[5], p[6]);
    case PrimitiveKind::Cone:
      return fmt::format(
          "apex: {:.9g} {:.9g} {:.9g}\naxis: {:.9g} {:.9g} {:.9g}\nhalf angle: {:.9g} degrees\n",
          p[0], p[1], p[2], p[3], p[4], p[5], p[6]);
    case PrimitiveKind::Quadric: {
      std::string s = "coefficients (x² y² z² xy yz xz x y z 1):";
      for (double c : p) s += fmt::format(" {:.9g}", c);
      return s + "\n";
    }
  }
  return "";
}

}  // namespace

void add_fit_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, primitive, loss = "huber";
    double loss_scale = 0;
    std::int64_t max_iterations = 100;
    bool no_normals = false;
    std::string q;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "fit",
      "Fit a plane, sphere, cylinder, cone or quadric to the points of a dataset; print it "
      "as a function expression (-f of sample and select)");
  cmd->add_option("input", args->in, "Input dataset (any type: its points are fitted)")->required();
  cmd->add_option("-p,--primitive", args->primitive, "plane, sphere, cylinder, cone or quadric")
      ->required()
      ->check(CLI::IsMember({"plane", "sphere", "cylinder", "cone", "quadric"}));
  cmd->add_option("--loss", args->loss,
                  "Robust loss on the distances: none, huber (default) or cauchy")
      ->check(CLI::IsMember({"none", "huber", "cauchy"}));
  auto* scale_opt = cmd->add_option("--loss-scale", args->loss_scale,
                                    "Scale of the robust loss, data units (default: from the "
                                    "median residual)")
                        ->check(positive_number());
  cmd->add_option("--max-iterations", args->max_iterations,
                  "Solver iterations per solve (default 100)")
      ->transform(integer_in(1, 100000));
  cmd->add_flag("--no-normals", args->no_normals,
                "Do not use the input's point normals to initialise the fit");
  auto* q_opt = add_q_option(*cmd, args->q);
  cmd->add_option("-o,--output", args->out,
                  "Write the function expression to this text file (atomically)");
  cmd->footer(
      "Prints the parameters, the residual statistics and the function in the expression\n"
      "language of docs/implicit.md; -o writes that expression alone, for -f \"$(cat FILE)\".\n"
      "Examples:\n"
      "  isoforge sample -f 'sphere(center=[1,2,3], r=2)' -b -2 4 -1 5 0 6 -d 32 -o ball.vti\n"
      "  isoforge contour ball.vti -v 0 -o ball.vtp\n"
      "  isoforge fit ball.vtp --primitive sphere -o ball.txt\n"
      "  isoforge sample -f \"$(cat ball.txt)\" -b -2 4 -1 5 0 6 -d 32 -o refit.vti\n"
      "  isoforge fit ball.vtp --primitive quadric --loss cauchy\n"
      "  isoforge fit data/bunny.ply --primitive plane --loss none");
  cmd->callback([args, &ctx, scale_opt, q_opt] {
    if (!args->out.empty()) check_writable(args->out);
    require_plot3d_input(q_opt, args->in);
    static const std::map<std::string, PrimitiveKind> kinds = {
        {"plane", PrimitiveKind::Plane},
        {"sphere", PrimitiveKind::Sphere},
        {"cylinder", PrimitiveKind::Cylinder},
        {"cone", PrimitiveKind::Cone},
        {"quadric", PrimitiveKind::Quadric}};
    static const std::map<std::string, RobustLoss> losses = {
        {"none", RobustLoss::None}, {"huber", RobustLoss::Huber}, {"cauchy", RobustLoss::Cauchy}};
    FitOptions o;
    o.kind = kinds.at(args->primitive);
    o.loss = losses.at(args->loss);
    require_meaningful(scale_opt, o.loss != RobustLoss::None,
                       "applies to a robust loss (huber, cauchy), not --loss none");
    o.loss_scale = args->loss_scale;
    o.max_iterations = static_cast<int>(args->max_iterations);
    o.use_normals = !args->no_normals;
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    ReadOptions ro;
    ro.plot3d_q = args->q;
    const Dataset ds = read_input(args->in, bar, ro);
    bar.stage("fitting");
    o.progress = bar.callback();
    const auto t0 = std::chrono::steady_clock::now();
    const auto [fitted, st] = fit_primitive(ds, o);
    const double ms = elapsed_ms(t0);
    if (!args->out.empty()) write_file_atomic(args->out, fitted.expression + "\n");
    bar.finish();
    fmt::print("{} fitted to {} points of {} (loss {}, {} solver iterations{})\n",
               to_string(o.kind), st.points, args->in, to_string(o.loss), st.iterations,
               st.converged ? "" : ", not converged");
    fmt::print("{}", parameters_text(fitted));
    fmt::print(
        "residuals{}: rms {:.6g}, median |r| {:.6g}, max |r| {:.6g}; inliers {} of {} "
        "({:.1f}%)\n",
        o.kind == PrimitiveKind::Quadric ? " (first-order distance)" : "", st.rms, st.median_abs,
        st.max_abs, st.inliers, st.points, 100.0 * double(st.inliers) / double(st.points));
    fmt::print("function: {}\n", fitted.expression);
    if (!ctx.quiet) {
      fmt::print(stderr, "fit: {:.1f} ms{}\n", ms,
                 args->out.empty() ? "" : fmt::format("; wrote {}", args->out));
    }
  });
}

}  // namespace isoforge::cli
