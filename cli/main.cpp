// nurbsgl: geometric queries on trimmed NURBS models with OpenGL fragment-shader GPGPU.
#include <fmt/format.h>

#include <exception>
#include <new>

#include "cli/commands.h"
#include "nurbs/io/output_file.h"
#include "nurbs/io/read_error.h"

int main(int argc, char** argv) {
  CLI::App app{
      "nurbsgl: geometric queries on trimmed NURBS models with fragment-shader GPGPU.\n"
      "Exit codes: 0 ok, 1 a check failed, 2 bad command line, input file or unwritable output, 3 no usable "
      "OpenGL.",
      "nurbsgl"};
  app.require_subcommand(1);
  app.fallthrough();  // global options (--gl, --dump, --profile, --gl-threads) also after the subcommand
  cli::GlobalOptions global;
  app.add_option("--gl", global.gl,
                 "GL backend: auto (EGL, then OSMesa), egl, egl-device, osmesa, glfw "
                 "(default: $NURBSGL_GL, else auto)")
      ->check(CLI::IsMember({"auto", "egl", "egl-device", "osmesa", "glfw"}));
  app.add_option("--dump", global.dump_dir, "Write the textures a command produces as OpenEXR files into DIR");
  app.add_flag("--profile", global.profile, "Print GPU and CPU time per pass (synchronised) on stderr");
  app.add_option("--gl-threads", global.gl_threads,
                 "Rasterizer threads of Mesa's software renderer llvmpipe (sets LP_NUM_THREADS; default: the "
                 "environment's, else one per core). 0 draws on the calling thread: faster for searches of many "
                 "small passes (clearance of the paper pair: about 2x per query), slower for large passes")
      ->check(CLI::Range(0, 256));
  cli::add_gpu_info(app, global);
  cli::add_selftest(app, global);
  cli::add_info(app, global);
  cli::add_generate(app, global);
  cli::add_evaluate(app, global);
  cli::add_distance(app, global);
  cli::add_clearance(app, global);
  cli::add_tessellate(app, global);
  cli::add_deviation(app, global);
  cli::add_raycast(app, global);
  cli::add_thickness(app, global);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);  // prints help (rc 0) or the usage error
    return rc == 0 ? cli::kOk : cli::kBadInput;
  } catch (const gpgpu::NoGlError& e) {
    fmt::print(stderr, "nurbsgl: {}\n", e.what());
    return cli::kNoGl;
  } catch (const nurbs::io::ReadError& e) {
    fmt::print(stderr, "nurbsgl: {}\n", e.what());
    return cli::kBadInput;
  } catch (const nurbs::io::WriteError& e) {  // an output file (checked before the work where possible)
    fmt::print(stderr, "nurbsgl: {}\n", e.what());
    return cli::kBadInput;
  } catch (const cli::BadInput& e) {
    fmt::print(stderr, "nurbsgl: {}\n", e.what());
    return cli::kBadInput;
  } catch (const cli::CommandFailed& e) {
    fmt::print(stderr, "nurbsgl: FAILED: {}\n", e.what());
    return cli::kFailed;
  } catch (const std::bad_alloc&) {  // what the up-front estimates did not foresee
    fmt::print(stderr, "nurbsgl: out of memory: the request needs more than this machine has free (a larger --tol, "
                       "fewer points or faces)\n");
    return cli::kBadInput;
  } catch (const std::exception& e) {
    fmt::print(stderr, "nurbsgl: error: {}\n", e.what());
    return cli::kFailed;
  } catch (...) {
    fmt::print(stderr, "nurbsgl: error: unknown exception\n");
    return cli::kFailed;
  }
  return cli::kOk;
}
