// The mvox command line. Exit codes: 0 success, 1 a failure in the job (bad input file, write
// error, ...), 2 a usage error (unknown option, missing argument). Every failure prints one line
// on standard error: "mvox: error: SUBJECT: PROBLEM".
#include <CLI/CLI.hpp>
#include <cstdio>
#include <stdexcept>

#include "commands.h"
#include "error.h"

int main(int argc, char** argv) {
  CLI::App app{
      "mvox: surface extraction by marching voxels, streamed two slices at a time in fixed "
      "memory.\nExamples:\n"
      "  mvox demo\n"
      "  mvox extract 'cthead/CThead.*' --raw 256x256:u16be -t 600 --spacing 1,1,2 -o head.ply\n"
      "  mvox extract engine_256x256x128_uint8.raw --raw 256x256x128:u8 -t 100 -o engine.ply\n"
      "  mvox extract 'mrbrain8bit/mrbrain-8bit*.png' -t 50 -o brain.ply",
      "mvox"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "mvox 0.1.0");
  mvox::add_extract_command(app);
  mvox::add_demo_command(app);
  mvox::add_phantom_command(app);
  mvox::add_render_command(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "mvox: error: %s\nRun 'mvox --help' or 'mvox COMMAND --help' for usage.\n",
                 e.what());
    return 2;
  } catch (const mvox::Error& e) {
    std::fprintf(stderr, "mvox: error: %s\n", e.what());
    return 1;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "mvox: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mvox: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
