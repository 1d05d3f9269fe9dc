// nurbsgl: geometric queries on trimmed NURBS models with OpenGL fragment-shader GPGPU.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <exception>
#include <new>
#include <string>
#include <string_view>
#include <vector>

#include "cli/commands.h"
#include "nurbs/io/output_file.h"
#include "nurbs/io/read_error.h"
#include "nurbs/request_error.h"

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
  app.add_flag("--accept-partial", global.accept_partial,
               "Certify answers on a model whose reader dropped faces, on the faces read (without it such answers "
               "exit 1; every command names the dropped faces either way)");
  app.add_flag("--strict", global.strict,
               "Exit 1 also for answers over the tolerance only by the file's precision (its edges lie off their "
               "faces: marked limited_by_file, certified to that precision; without it they exit 0)");
  cli::add_gpu_info(app, global);
  cli::add_selftest(app, global);
  cli::add_info(app, global);
  cli::add_generate(app, global);
  cli::add_evaluate(app, global);
  cli::add_distance(app, global);
  cli::add_clearance(app, global);
  cli::add_clash(app, global);
  cli::add_tessellate(app, global);
  cli::add_deviation(app, global);
  cli::add_inspect(app, global);
  cli::add_raycast(app, global);
  cli::add_thickness(app, global);

  // With --json anywhere, an error before the command's object is printed is one JSON object too
  // ({"error", "exit_code"} on stdout); the text stays on stderr.
  bool json = false;
  for (int k = 1; k < argc; ++k) json |= std::string_view(argv[k]) == "--json";
  // Control bytes (quoted from a bad file or argument) are escaped in every message.
  const auto fail = [&](int rc, const std::string& message) {
    const std::string text = nurbs::io::printable(message, true);
    fmt::print(stderr, "{}\n", text);
    if (json && !cli::json_printed()) cli::print_json({{"error", text}, {"exit_code", rc}});
    return rc;
  };
  // A first word that names no command: the commands nearest to it.
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) names.push_back(sub->get_name());
  for (int k = 1; k < argc; ++k) {
    const std::string_view word(argv[k]);
    if (word == "--gl" || word == "--dump" || word == "--gl-threads") {
      ++k;  // its value
      continue;
    }
    if (word.empty() || word[0] == '-') continue;
    if (std::find(names.begin(), names.end(), word) == names.end()) {
      const std::vector<std::string> near = cli::closest_names(std::string(word), names);
      return fail(cli::kBadInput,
                  fmt::format("nurbsgl: '{}' is not a command{}; `nurbsgl --help` lists them", word,
                              near.empty() ? "" : fmt::format(" (did you mean {}?)", fmt::join(near, " or "))));
    }
    break;
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e), cli::kOk;  // --help
    if (!json) return app.exit(e), cli::kBadInput;               // the usage error and its hint
    return fail(cli::kBadInput, fmt::format("nurbsgl: {}", e.what()));
  } catch (const gpgpu::NoGlError& e) {
    return fail(cli::kNoGl, fmt::format("nurbsgl: {}", e.what()));
  } catch (const nurbs::io::ReadError& e) {
    return fail(cli::kBadInput, fmt::format("nurbsgl: {}", e.what()));
  } catch (const nurbs::io::WriteError& e) {  // an output file (checked before the work where possible)
    return fail(cli::kBadInput, fmt::format("nurbsgl: {}", e.what()));
  } catch (const nurbs::RequestError& e) {  // a request the library will not answer as asked
    return fail(cli::kBadInput, fmt::format("nurbsgl: {}", e.what()));
  } catch (const cli::BadInput& e) {
    return fail(cli::kBadInput, fmt::format("nurbsgl: {}", e.what()));
  } catch (const cli::CommandFailed& e) {
    return fail(cli::kFailed, fmt::format("nurbsgl: FAILED: {}", e.what()));
  } catch (const std::bad_alloc&) {  // what the up-front estimates did not foresee
    return fail(cli::kBadInput,
                "nurbsgl: out of memory: the request needs more than this machine has free (a larger --tol, fewer "
                "points or faces)");
  } catch (const std::exception& e) {
    return fail(cli::kFailed, fmt::format("nurbsgl: error: {}", e.what()));
  } catch (...) {
    return fail(cli::kFailed, "nurbsgl: error: unknown exception");
  }
  return cli::kOk;
}
