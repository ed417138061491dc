// isoforge glyph: a cone, arrow, sphere, cube, line (hedgehog) or any polydata at (masked)
// points of a dataset, turned to its vectors or normals and scaled by a scalar or vector length.

#include <fmt/core.h>

#include <chrono>
#include <filesystem>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/filters/glyph.hpp"
#include "isoforge/filters/tensor_glyph.hpp"
#include "isoforge/io/io.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

void add_glyph_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, q, source = "cone", orient = "auto", scale_by = "none", color,
                vectors, normals, scalars;
    std::int64_t resolution = 6, every = 0, random = 0, max_points = 0, seed = 0;
    double factor = 1, voxel = 0;
    std::vector<double> range;
    bool clamp = false, no_ids = false, no_point_data = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "glyph", "Place a shape (cone, arrow, sphere, cube, line or a polydata file) at the points "
               "of a dataset, turned to its vectors or normals and scaled");
  cmd->add_option("input", args->in, "Input dataset (any format isoforge reads)")->required();
  cmd->add_option("-o,--output", args->out, "Output: " + std::string(kSurfaceExtensions))
      ->required();
  cmd->add_option("-s,--source", args->source,
                  "cone, arrow, sphere, cube, line (one line per point: a hedgehog) or a "
                  "polydata FILE (default cone)");
  auto* res_opt = cmd->add_option("--resolution", args->resolution,
                                  "Sides of the cone and arrow, slices of the sphere (default 6)")
                      ->transform(integer_in(3, 1024));
  cmd->add_option("--orient", args->orient,
                  "auto (vectors, else normals, else none), vectors, normals or none")
      ->check(CLI::IsMember({"auto", "vectors", "normals", "none"}));
  auto* vectors_opt = cmd->add_option("--vectors", args->vectors,
                                      "Point array of vectors (default: active vectors)");
  auto* normals_opt = cmd->add_option("--normals", args->normals,
                                      "Point array of normals (default: active normals)");
  auto* scalars_opt = cmd->add_option("--scalars", args->scalars,
                                      "Point array of scalars (default: active scalars)");
  cmd->add_option("--scale-by", args->scale_by, "scalar, vector (its length) or none (default)")
      ->check(CLI::IsMember({"scalar", "vector", "none"}));
  cmd->add_option("-f,--factor", args->factor,
                  "Glyph size: source units times this (times the scale value; default 1)")
      ->check(finite_number());
  auto* clamp_opt = cmd->add_flag("--clamp", args->clamp,
                                  "Map the scale value's range to [0, 1] before the factor");
  auto* range_opt = cmd->add_option("--range", args->range,
                                    "With --clamp: the value range mapped to [0, 1] (MIN MAX; "
                                    "default: the data's range)")
                        ->expected(2)
                        ->check(finite_number());
  cmd->add_option("--glyph-color", args->color,
                  "Add a point array 'GlyphColor': scalar, magnitude (of the vectors) or index "
                  "(of the glyph)")
      ->check(CLI::IsMember({"scalar", "magnitude", "index"}));
  auto* every_opt = cmd->add_option("--mask-every", args->every, "Glyph every Nth point (N >= 1)")
                        ->transform(integer_in(1));
  auto* random_opt = cmd->add_option("--mask-random", args->random,
                                     "Glyph N points chosen at random (see --seed)")
                         ->transform(integer_in(1));
  auto* seed_opt = cmd->add_option("--seed", args->seed, "Seed of --mask-random (default 0)")
                       ->transform(integer_in(0));
  auto* voxel_opt = cmd->add_option("--mask-voxel", args->voxel,
                                    "Glyph one point per cube of this edge (data units)")
                        ->check(positive_number());
  cmd->add_option("--mask-max", args->max_points,
                  "At most N glyphs, spread evenly over the chosen points")
      ->transform(integer_in(1));
  cmd->add_flag("--no-point-ids", args->no_ids, "Leave out the point array 'InputPointIds'");
  cmd->add_flag("--no-point-data", args->no_point_data,
                "Do not copy the input's point arrays to the glyphs");
  auto* q_opt = add_q_option(*cmd, args->q);
  cmd->footer(
      "The output is one polydata: the glyphs' triangles (lines for a hedgehog) with their\n"
      "point normals, the input point of each output point ('InputPointIds') and the input's\n"
      "point arrays.\n"
      "Examples:\n"
      "  isoforge normals data/fran_cut.vtk --flip -o fran_normals.vtp\n"
      "  isoforge glyph fran_normals.vtp --orient normals -f 0.01 --mask-random 220 --seed 1 -o "
      "spikes.vtp   (Fig. 1.30)\n"
      "  isoforge glyph data/combxyz.bin --q data/combq.bin -s arrow --scale-by vector -f 0.004 "
      "--mask-every 20 -o arrows.vtp\n"
      "  isoforge glyph data/combxyz.bin --q data/combq.bin -s line --scale-by vector -f 0.002 "
      "-o hedgehog.vtp\n"
      "  isoforge glyph data/bunny.ply -s sphere --scalars intensity --scale-by scalar --clamp "
      "-f 0.004 --mask-voxel 0.01 -o dots.ply\n"
      "  isoforge glyph data/hello.vtk -s data/fran_cut.vtk --orient none -f 2 -o hello_faces.vtp"
      "   (any polydata as the shape)");
  cmd->callback([args, &ctx, vectors_opt, normals_opt, scalars_opt, res_opt, clamp_opt, range_opt,
                 every_opt, random_opt, seed_opt, voxel_opt, q_opt] {
    (void)output_format(args->out, kSurfaceFormats, kSurfaceExtensions);
    require_plot3d_input(q_opt, args->in);
    exclude_each_other({every_opt, random_opt, voxel_opt});
    require_meaningful(seed_opt, random_opt->count() > 0, "applies to --mask-random only");
    // An array named for a use the other options turn off is an error, not silently unused.
    const bool orient_vectors = args->orient == "auto" || args->orient == "vectors";
    const bool orient_normals = args->orient == "auto" || args->orient == "normals";
    require_meaningful(
        vectors_opt, orient_vectors || args->scale_by == "vector" || args->color == "magnitude",
        "unused: give --orient vectors, --scale-by vector or --glyph-color magnitude");
    require_meaningful(normals_opt, orient_normals, "unused: give --orient normals (or auto)");
    require_meaningful(scalars_opt, args->scale_by == "scalar" || args->color == "scalar",
                       "unused: give --scale-by scalar or --glyph-color scalar");
    require_meaningful(range_opt, clamp_opt->count() > 0, "applies with --clamp only");
    require_meaningful(clamp_opt, args->scale_by != "none",
                       "clamps the scale value: give --scale-by scalar or vector");
    static const std::vector<std::string> kShapes = {"cone", "arrow", "sphere", "cube", "line"};
    const auto shape_it = std::find(kShapes.begin(), kShapes.end(), args->source);
    const bool builtin = shape_it != kShapes.end();
    require_meaningful(res_opt, builtin && args->source != "cube" && args->source != "line",
                       "applies to the cone, arrow and sphere only");
    if (!builtin && !std::filesystem::exists(args->source)) {
      throw UsageError("--source: '" + args->source +
                       "' is neither cone, arrow, sphere, cube, line nor an existing file");
    }
    const auto range = parse_color_range(args->range, "--range");  // MIN < MAX, finite width
    GlyphOptions o;
    o.orient = args->orient == "vectors"   ? GlyphOrient::Vectors
               : args->orient == "normals" ? GlyphOrient::Normals
               : args->orient == "none"    ? GlyphOrient::None
                                           : GlyphOrient::Auto;
    o.scale = args->scale_by == "scalar"   ? GlyphScale::Scalar
              : args->scale_by == "vector" ? GlyphScale::Vector
                                           : GlyphScale::None;
    o.color = args->color == "scalar"      ? GlyphColor::Scalar
              : args->color == "magnitude" ? GlyphColor::Magnitude
              : args->color == "index"     ? GlyphColor::Index
                                           : GlyphColor::None;
    o.factor = args->factor;
    o.clamp = args->clamp;
    o.range = range;
    o.vectors = args->vectors;
    o.normals = args->normals;
    o.scalars = args->scalars;
    o.mask.every = static_cast<std::size_t>(args->every);
    o.mask.random = static_cast<std::size_t>(args->random);
    o.mask.seed = static_cast<std::uint64_t>(args->seed);
    o.mask.voxel = args->voxel;
    o.mask.max_points = static_cast<std::size_t>(args->max_points);
    o.point_ids = !args->no_ids;
    o.carry_point_data = !args->no_point_data;

    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    ReadOptions ro;
    ro.plot3d_q = args->q;
    const Dataset input = read_input(args->in, bar, ro);
    PolyData source;
    if (builtin) {
      source = glyph_source(static_cast<GlyphShape>(shape_it - kShapes.begin()),
                            static_cast<int>(args->resolution));
    } else {
      source = read_polydata(args->source, bar, "glyph: the --source file must hold polygonal data");
    }
    bar.stage("glyphing");
    o.progress = bar.callback();
    const auto t0 = std::chrono::steady_clock::now();
    auto [out, stats] = builtin ? glyph(input, static_cast<GlyphShape>(shape_it - kShapes.begin()),
                                        o, static_cast<int>(args->resolution))
                                : glyph(input, source, o);
    const double ms = elapsed_ms(t0);
    write_output(out, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr,
                 "wrote {}: {} glyphs ({} of {} points; {}, {} points and {} cells each), {} "
                 "points, {} cells in {:.3f} s\n",
                 args->out, stats.glyphs, stats.glyphs, num_points(input), args->source,
                 stats.source_points, stats.source_cells, out.num_points(), out.num_cells(),
                 ms / 1000);
      fmt::print(stderr, "  oriented by {}, sized by {} (sizes {:.4g} .. {:.4g})\n",
                 stats.orient_array.empty() ? "nothing" : "'" + stats.orient_array + "'",
                 stats.scale_array.empty() ? "nothing" : "'" + stats.scale_array + "'",
                 stats.min_scale, stats.max_scale);
    }
  });
}

void add_tensor_glyph_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, q, tensors, color = "eigenvalue", shape = "ellipsoid";
    std::int64_t resolution = 12, every = 0, max_points = 0;
    double scale = 1, max_size = 0, gamma = 3;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "tensor-glyph",
      "Ellipsoids or superquadrics showing a tensor field: axes along the eigenvectors, sized by "
      "the eigenvalues (vtkTensorGlyph)");
  cmd->add_option("input", args->in, "Input dataset with a point tensor array (any type)")
      ->required();
  cmd->add_option("-o,--output", args->out, "Output: " + std::string(kSurfaceExtensions))
      ->required();
  cmd->add_option("-a,--array", args->tensors,
                  "Tensor point array: 9 components (3x3) or 6 (symmetric: XX YY ZZ XY YZ XZ); "
                  "default: the active tensors");
  cmd->add_option("-s,--scale", args->scale, "Semi-axis = scale x |eigenvalue| (default 1)")
      ->check(positive_number());
  cmd->add_option("--max-size", args->max_size,
                  "Shrink glyphs whose largest semi-axis exceeds this (data units)")
      ->check(positive_number());
  cmd->add_option("-r,--resolution", args->resolution, "Slices of each ellipsoid (N >= 3, default 12)")
      ->transform(integer_in(3, 1024));
  cmd->add_option("--shape", args->shape,
                  "ellipsoid (default) or superquadric (Kindlmann: cylinder for a linear tensor, "
                  "disc for a planar one)")
      ->check(CLI::IsMember({"ellipsoid", "superquadric"}));
  auto* gamma_opt = cmd->add_option("--gamma", args->gamma,
                                    "Superquadric edge sharpness, > 0 (default 3)")
                        ->check(positive_number());
  cmd->add_option("--color-by", args->color,
                  "The point scalar 'TensorColor': eigenvalue (the largest), anisotropy "
                  "(fractional, 0 to 1) or none")
      ->check(CLI::IsMember({"eigenvalue", "anisotropy", "none"}));
  cmd->add_option("--mask-every", args->every, "Glyph every Nth point (N >= 1)")
      ->transform(integer_in(1));
  cmd->add_option("--mask-max", args->max_points, "At most N glyphs, spread evenly over the points")
      ->transform(integer_in(1));
  auto* q_opt = add_q_option(*cmd, args->q);
  cmd->footer(
      "Only the upper triangle of a 3x3 tensor is read (it is taken as symmetric, as VTK does).\n"
      "Method: docs/algorithms/tensor_glyph.md.\n"
      "Examples:\n"
      "  isoforge gradient data/office.binary.vtk -a vectors --name strain -o office_grad.vts\n"
      "  isoforge tensor-glyph office_grad.vts -a strain -s 0.2 --max-size 0.1 --mask-every 7 \\\n"
      "      --color-by anisotropy -o office_ellipsoids.vtp\n"
      "  isoforge point-load --dims 12 -o load.vti\n"
      "  isoforge tensor-glyph load.vti -s 0.3 --max-size 0.08 --shape superquadric -o sq.vtp");
  cmd->callback([args, &ctx, q_opt, gamma_opt] {
    (void)output_format(args->out, kSurfaceFormats, kSurfaceExtensions);
    require_meaningful(gamma_opt, args->shape == "superquadric", "applies to --shape superquadric");
    require_plot3d_input(q_opt, args->in);
    TensorGlyphOptions o;
    o.tensors = args->tensors;
    o.scale = args->scale;
    o.max_size = args->max_size;
    o.resolution = static_cast<int>(args->resolution);
    o.shape = args->shape == "superquadric" ? TensorGlyphShape::Superquadric
                                            : TensorGlyphShape::Ellipsoid;
    o.gamma = args->gamma;
    o.color = args->color == "none"         ? TensorColor::None
              : args->color == "anisotropy" ? TensorColor::Anisotropy
                                            : TensorColor::Eigenvalue;
    o.mask.every = static_cast<std::size_t>(args->every);
    o.mask.max_points = static_cast<std::size_t>(args->max_points);
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    ReadOptions ro;
    ro.plot3d_q = args->q;
    const Dataset input = read_input(args->in, bar, ro);
    bar.stage("glyphs");
    o.progress = bar.callback();
    const auto t0 = std::chrono::steady_clock::now();
    const auto [out, stats] = tensor_glyph(input, o);
    const double ms = elapsed_ms(t0);
    write_output(out, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr,
                 "wrote {}: {} {} ({} flat or collapsed), {} triangles in {:.3f} s; "
                 "eigenvalues {:.4g} .. {:.4g}\n",
                 args->out, stats.glyphs,
                 args->shape == "superquadric" ? "superquadrics" : "ellipsoids", stats.degenerate,
                 out.polys.size(), ms / 1000, stats.min_eigenvalue, stats.max_eigenvalue);
    }
  });
}

}  // namespace isoforge::cli
