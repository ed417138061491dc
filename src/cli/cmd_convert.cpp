// isoforge convert IN OUT: format conversion chosen by the extensions.

#include <fmt/core.h>

#include <cmath>
#include <limits>
#include <optional>

#include "commands.hpp"
#include "common.hpp"
#include "draco_options.hpp"
#include "isoforge/filters/colormap.hpp"
#include "isoforge/io/atomic_file.hpp"
#include "isoforge/io/draco.hpp"
#include "isoforge/io/gltf.hpp"
#include "isoforge/io/io.hpp"
#include "isoforge/io/vtk_xml.hpp"
#include "progress_bar.hpp"

namespace isoforge::cli {

void add_convert_command(CLI::App& app, Context& ctx) {
  struct Args {
    std::string in, out, q, legacy_version = "4.2", grid;
    bool ascii = false, no_compress = false, vtk_xml = false;
    double vdb_tolerance = 0;
    std::string codec;
    ColorBy color_by;
  };
  auto args = std::make_shared<Args>();
  auto draco = std::make_shared<DracoCli>();
  auto* cmd = app.add_subcommand("convert",
                                 "Convert a dataset between formats (chosen by the "
                                 "file extensions)");
  cmd->add_option("input", args->in, "Input file")->required();
  cmd->add_option("output", args->out,
                  "Output file: .vtk .vti .vts .vtp .vtu .ply .obj .off .vdb .drc .glb")
      ->required();
  auto* q_opt = add_q_option(*cmd, args->q);
  auto* grid_opt = add_grid_option(*cmd, args->grid);
  auto* ascii_opt =
      cmd->add_flag("--ascii", args->ascii, "Write text instead of binary (VTK legacy/XML, PLY)");
  cmd->add_flag("--vtk-xml", args->vtk_xml,
                "Write VTK XML with the extension that fits the dataset (.vti .vts .vtp .vtu), "
                "replacing any extension OUTPUT has");
  auto* no_compress_opt = cmd->add_flag("--no-compress", args->no_compress,
                                        "VTK XML: do not zlib-compress binary data");
  auto* legacy_opt =
      cmd->add_option(
             "--legacy-version", args->legacy_version,
             "VTK legacy output: header version 4.2 (classic) or 5.1 (offsets/connectivity)")
          ->check(CLI::IsMember({"4.2", "5.1"}));
  auto* tolerance_opt =
      cmd->add_option("--vdb-tolerance", args->vdb_tolerance,
                      "OpenVDB output: values within this of the background stay inactive (>= 0)")
          ->check(number_in(0, std::numeric_limits<float>::max()));
  auto* codec_opt =
      cmd->add_option("--codec", args->codec,
                      "glTF output: how meshes are stored: draco, meshopt (lossless, fast to "
                      "decode) or none (default: " +
                          std::string(gltf_codec_name(WriteOptions{}.gltf_codec)) + ")")
          ->check(CLI::IsMember({"draco", "meshopt", "none"}));
  add_draco_options(*cmd, *draco);
  add_color_by_options(*cmd, args->color_by);
  cmd->footer(
      "The output is written atomically: a failed run leaves no partial file and keeps an\n"
      "existing file unchanged. A format that cannot hold the dataset is an error.\n"
      "Draco (.drc) output is decoded again after writing and measured: the size, the ratio to\n"
      "raw float32/int32 data and the largest error of the positions and of every array are\n"
      "printed; with --max-error(-rel) the quantization is the coarsest that meets it.\n"
      "Examples:\n"
      "  isoforge convert data/fran_cut.vtk fran.vtp\n"
      "  isoforge convert data/post.vtk post --vtk-xml      (writes post.vtu)\n"
      "  isoforge convert data/ironProt.vtk iron.vti --compressor lz4   (fast VTK XML)\n"
      "  isoforge convert data/ironProt.vtk iron_small.vti --level 9\n"
      "  isoforge convert data/fran_cut.vtk fran64.vtp --id-type int64   (64-bit cell ids, as "
      "VTK)\n"
      "  isoforge convert data/combxyz.bin --q data/combq.bin combustor.vts\n"
      "  isoforge convert data/bunny.ply bunny.vtk --ascii --legacy-version 5.1\n"
      "  isoforge convert data/HeadMRVolume.mhd head.vdb    (OpenVDB needs equal spacing on all "
      "axes)\n"
      "  isoforge convert data/bunny.ply bunny.drc --max-error-rel 1e-4\n"
      "  isoforge convert data/bunny.ply bunny16.drc --bits 16 --level 10\n"
      "  isoforge convert bunny.drc bunny_back.vtp\n"
      "  isoforge convert data/bunny.ply bunny_seq.drc --sequential --max-error 1e-5 \\\n"
      "      --array-error confidence=0.001\n"
      "  isoforge convert data/bunny.ply bunny.glb --codec meshopt   (glTF binary; see isoforge "
      "view)\n"
      "  isoforge convert data/bunny.ply bunny_c.glb --color-by intensity --colormap plasma\n"
      "  isoforge convert data/post.vtk post.vtu --color-by Pressure --colormap black-body");
  cmd->callback([cmd, args, draco, &ctx, q_opt, grid_opt, ascii_opt, no_compress_opt,
                 legacy_opt, tolerance_opt, codec_opt] {
    require_plot3d_input(q_opt, args->in);
    require_vdb_input(grid_opt, args->in);
    // The output format: VTK XML of some kind with --vtk-xml, else by the extension. Fail on an
    // unknown or unwritable one, or an option it ignores, before doing any reading.
    const FileFormat format = args->vtk_xml ? FileFormat::VtkPolyData : format_of(args->out);
    const bool xml = args->vtk_xml || format == FileFormat::VtkImageData ||
                     format == FileFormat::VtkStructuredGrid || format == FileFormat::VtkPolyData ||
                     format == FileFormat::VtkUnstructuredGrid;
    if (format == FileFormat::Plot3d || format == FileFormat::Nrrd ||
        format == FileFormat::MetaImage) {
      throw UsageError(args->out + ": writing " + std::string(format_name(format)) +
                       " is not supported (write .vts, .vti or .vtk instead)");
    }
    require_meaningful(
        ascii_opt, xml || format == FileFormat::VtkLegacy || format == FileFormat::Ply,
        "applies to VTK and PLY output (OBJ and OFF are always text, OpenVDB binary)");
    require_meaningful(no_compress_opt, xml, "applies to VTK XML output only");
    exclude_each_other({ascii_opt, no_compress_opt});
    require_meaningful(legacy_opt, !args->vtk_xml && format == FileFormat::VtkLegacy,
                       "applies to VTK legacy output (.vtk) only");
    require_meaningful(tolerance_opt, format == FileFormat::Vdb, "applies to OpenVDB output only");
    require_meaningful(codec_opt, format == FileFormat::Glb, "applies to glTF output (.glb) only");
    const bool drc = !args->vtk_xml && format == FileFormat::Draco;
    const bool glb = !args->vtk_xml && format == FileFormat::Glb;
    const GltfCodec codec =
        args->codec.empty() ? WriteOptions{}.gltf_codec : gltf_codec_from_name(args->codec);
    const bool draco_out = drc || (glb && codec == GltfCodec::Draco);
    check_draco_options(*draco, draco_out,
                        "applies to Draco output (.drc, or .glb with the draco codec) only");
    // --level: Draco's or VTK XML's; --compressor: VTK XML's (add_xml_compression_options).
    const CLI::Option* compressor_opt = cmd->get_option("--compressor");
    if (draco_out) {
      require_meaningful(compressor_opt, false, "applies to VTK XML output only, not Draco");
      require_meaningful(cmd->get_option("--id-type"), false,
                         "applies to VTK XML output only, not Draco");
    } else if (const std::string given = xml_option_given(); !xml && !given.empty()) {
      throw UsageError(given + ": applies to VTK XML (.vti .vts .vtp .vtu)" +
                       (given == "--id-type" ? "" : " and Draco") + " output only, not " +
                       args->out);
    } else if (xml) {
      check_xml_compression(args->vtk_xml ? FileFormat::VtkPolyData : format, args->out);
      exclude_each_other({compressor_opt, no_compress_opt});
      exclude_each_other({draco->level_opt, no_compress_opt});
      exclude_each_other({compressor_opt, ascii_opt});
      exclude_each_other({draco->level_opt, ascii_opt});
    }
    const DracoWriteOptions draco_options = draco_write_options(*draco);
    if (drc || (glb && codec == GltfCodec::Draco)) keep_freed_memory();
    check_color_by(args->color_by, format);
    check_writable(args->out);
    ReadOptions ro;
    ro.plot3d_q = args->q;
    ro.vdb_grid = args->grid;
    WriteOptions wo;
    wo.binary = !args->ascii;
    wo.compress = !args->no_compress;
    wo.vtk_legacy_version = args->legacy_version;
    wo.vdb_tolerance = args->vdb_tolerance;
    wo.gltf_codec = codec;
    ProgressBar bar(!ctx.quiet && stderr_is_tty());
    bar.stage("reading");
    Dataset ds = read_input(args->in, bar, ro);
    require_color_array(args->color_by, ds, false);
    // .glb: the colours come with a legend (the map, its range) that the viewer draws.
    std::optional<GltfLegend> legend;
    std::string colored;
    if (glb && !args->color_by.array.empty() && std::holds_alternative<PolyData>(ds)) {
      ColormapOptions co;
      co.map = colormap_from_name(args->color_by.map);
      co.range = parse_color_range(args->color_by.range, "--color-range");
      const ColormapStats cs = add_colors(std::get<PolyData>(ds), args->color_by.array, co);
      if (std::isfinite(cs.range[0]) && std::isfinite(cs.range[1])) {
        constexpr std::size_t kLegendColors = 32;  // a smooth bar; 128 bytes of JSON per mesh
        legend = GltfLegend{args->color_by.array,
                            args->color_by.map,
                            cs.range[0],
                            cs.range[1],
                            false,
                            colormap_table(co.map, kLegendColors)};
      }
      colored = fmt::format("coloured by '{}' ({}, range {:g} .. {:g})", args->color_by.array,
                            args->color_by.map, cs.range[0], cs.range[1]);
    } else {
      colored = apply_color_by(args->color_by, ds);
    }
    std::filesystem::path out = args->out;
    if (args->vtk_xml) out.replace_extension(vtk_xml_extension(ds));
    if (drc) {
      const auto* pd = std::get_if<PolyData>(&ds);
      if (!pd) {
        throw Error(out.string() + ": Draco holds polygonal data only, not " +
                    std::string(dataset_type_name(ds)) + " (try .vtk or " +
                    std::string(vtk_xml_extension(ds)) + ")");
      }
      bar.stage("writing");
      DracoWriteOptions o = draco_options;
      o.progress = bar.callback();
      const DracoStats st = write_draco(*pd, out, o);
      bar.finish();
      if (!ctx.quiet) print_draco_stats(st, out.string());
      return;
    }
    if (glb) {  // glTF: the stats of each mesh (Draco: measured errors) are printed
      const auto* pd = std::get_if<PolyData>(&ds);
      if (!pd) {
        throw Error(out.string() + ": glTF holds polygonal data only, not " +
                    std::string(dataset_type_name(ds)) + " (try .vtk or " +
                    std::string(vtk_xml_extension(ds)) + ")");
      }
      bar.stage("writing");
      GltfWriteOptions o;
      o.codec = codec;
      o.draco = draco_options;
      o.progress = bar.callback();
      const GltfMesh mesh{std::filesystem::path(args->in).stem().string(), *pd, legend,
                          legend && pd->point_data.has("Colors") ? "Colors" : ""};
      const GltfWriteStats st = write_gltf(std::span(&mesh, 1), out, o);
      bar.finish();
      if (!ctx.quiet) {
        print_gltf_stats(st, out.string());
        if (!colored.empty()) fmt::print(stderr, "  {}\n", colored);
      }
      return;
    }
    write_output(ds, out, bar, wo);
    bar.finish();
    if (!ctx.quiet) {
      fmt::print(stderr, "wrote {} ({} points, {} cells)\n", out.string(), num_points(ds),
                 num_cells(ds));
      if (!colored.empty()) fmt::print(stderr, "  {}\n", colored);
    }
  });
}

}  // namespace isoforge::cli
