// isoforge csg: booleans of two distance fields / level sets (OpenVDB or images).

#include <fmt/core.h>

#include "commands.hpp"
#include "common.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/model/csg.hpp"
#include "progress_bar.hpp"
#include "vdb_commands.hpp"

namespace isoforge::cli {

void add_csg_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string op, a, b, out;
    double offset_a = 0, offset_b = 0;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "csg",
      "Union, intersection or difference (A minus B) of two distance fields / level sets "
      "on the same grid: OpenVDB level sets (.vdb) or images (.vti .vtk)");
  cmd->add_option("operation", args->op, "union, intersection or difference")
      ->required()
      ->check(CLI::IsMember({"union", "intersection", "difference"}));
  cmd->add_option("a", args->a, "Field A (.vdb level set or image data)")->required();
  cmd->add_option("b", args->b, "Field B (same kind and grid as A)")->required();
  cmd->add_option("--offset-a", args->offset_a,
                  "Offset A first by this distance (makes an unsigned distance field a solid)")
      ->check(finite_number());
  cmd->add_option("--offset-b", args->offset_b, "Offset B first by this distance")
      ->check(finite_number());
  cmd->add_option("-o,--output", args->out,
                  "Output: a field of A's kind (.vdb, .vti), or its zero surface (.vtp .ply ...)")
      ->required();
  cmd->footer(
      "Fields are negative inside. Unsigned distance fields become solids with --offset-a/-b.\n"
      "Examples:\n"
      "  isoforge distance data/hello.vtk -m 0.8 --voxel-size 0.05 -b -1 10 -1 3 -1 1 -o hello.vdb\n"
      "  isoforge sample -f 'sphere(center=[4.5,1,0], r=1.2)' -b -1 10 -1 3 -1 1 --voxel-size 0.05 \\\n"
      "      -o ball.vdb\n"
      "  isoforge csg difference hello.vdb ball.vdb --offset-a 0.25 -o carved.vtp\n"
      "  isoforge sample -f 'box()' -b -1 1 -1 1 -1 1 -d 64 -o a.vti\n"
      "  isoforge sample -f 'sphere(r=1.2)' -b -1 1 -1 1 -1 1 -d 64 -o b.vti\n"
      "  isoforge csg difference a.vti b.vti -o a_minus_b.vti");
  cmd->callback([args, &ctx] {
    const CsgOperation op = csg_operation_from_name(args->op);
    const bool sparse_a = format_of(args->a) == FileFormat::Vdb;
    const bool sparse_b = format_of(args->b) == FileFormat::Vdb;
    if (sparse_a != sparse_b) throw UsageError("A and B must both be .vdb or both be image data");
    std::vector<FileFormat> outputs = kSurfaceFormats;
    outputs.push_back(sparse_a ? FileFormat::Vdb : FileFormat::VtkImageData);
    const FileFormat out_format =
        output_format(args->out, outputs,
                      std::string(sparse_a ? ".vdb" : ".vti") + " (the field) or " +
                          std::string(kSurfaceExtensions) + " (its zero surface)");
    const bool out_field = out_format == FileFormat::Vdb || out_format == FileFormat::VtkImageData;
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    // An empty result is written (it is the answer), with a warning naming the field's range.
    const auto warn_empty = [&](const std::string& range) {
      bar.finish();
      warn(fmt::format("csg: the {} is empty (no value <= 0): {}", args->op, range));
    };
    bar.stage("reading");
    PolyData surface;
    if (sparse_a) {
      auto result = vdb_commands().csg(args->a, args->b, args->offset_a, args->offset_b, op,
                                       args->op, out_field, args->out, ctx.quiet, bar);
      if (!result) return;  // the field, written
      surface = std::move(*result);
    } else {
      const auto image_of = [&bar](const std::string& path) {
        Dataset ds = read_input(path, bar);
        if (auto* img = std::get_if<ImageData>(&ds)) return std::move(*img);
        throw Error("csg: " + path + " is " + std::string(dataset_type_name(ds)) +
                    ", not image data");
      };
      ImageData a = image_of(args->a), b = image_of(args->b);
      if (args->offset_a != 0) a = offset(a, args->offset_a);
      if (args->offset_b != 0) b = offset(b, args->offset_b);
      bar.stage("csg");
      ImageData r = csg(a, b, op);
      const std::string range = range_text(*r.point_data.scalars());
      if (out_field) {
        if (!(r.point_data.scalars()->range().first <= 0)) warn_empty(range);
        write_output(r, args->out, bar);
        bar.finish();
        if (!ctx.quiet) fmt::print(stderr, "wrote {}: {} samples\n", args->out, r.num_points());
        return;
      }
      bar.stage("contouring");
      surface = offset_surfaces(r, {0.0}).output;
      if (surface.num_points() == 0) warn_empty(range);
    }
    write_output(surface, args->out, bar);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr, "wrote {}: {} points, {} triangles\n", args->out, surface.num_points(),
                 surface.polys.size());
    }
  });
}

}  // namespace isoforge::cli
