// The mvox command line. Exit codes: 0 success, 1 a failure in the job (bad input file, write
// error, ...), 2 a usage error (unknown option, missing argument). Every failure prints one line
// on standard error: "mvox: error: SUBJECT: PROBLEM". An interrupt (SIGINT, SIGTERM, SIGHUP,
// SIGQUIT, SIGUSR1, SIGALRM, SIGXCPU) exits with 128 + the signal's number, 130 for SIGINT, and
// a reader that closes an output pipe early ends mvox quietly, as SIGPIPE would (termination.h).
#include <poll.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstdio>
#include <iostream>
#include <new>
#include <stdexcept>
#include <string>

#include "cli/commands.h"
#include "error.h"
#include "failed_allocation.h"
#include "message_line.h"
#include "pipeline/memory_plan.h"
#include "pipeline/termination.h"
#include "write/standard_descriptors.h"

namespace {

// A failed job: one line, unless it failed because the reader of an output pipe went away.
int job_failure(const std::exception& e, int exit_code) {
  if (mvox::broken_pipe_noted()) mvox::exit_for_broken_pipe();
  mvox::print_message("error", e.what());
  return exit_code;
}

// What a command printed on standard output (--dry-run's plan, --help, --version) is flushed
// and checked once, at the end: onto a full disk it was lost with exit 0. A reader that went
// away ends mvox quietly, as for an output pipe.
int checked_standard_output(int status) {
  errno = 0;
  std::cout.flush();  // synced with stdio: a failed write shows in ferror(stdout) and errno
  const bool failed = std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout.good();
  if (!failed || status != 0) return status;
  // errno is EPIPE when the failed write was this flush's; an earlier flush may have failed
  // instead, and then a pipe whose reader is gone shows as an error on its write end.
  pollfd out{STDOUT_FILENO, 0, 0};
  if (errno == EPIPE || (::poll(&out, 1, 0) == 1 && (out.revents & POLLERR)))
    mvox::exit_for_broken_pipe();
  mvox::print_message("error", "standard output: write failed" +
                                   (errno != 0 ? ": " + mvox::errno_text(errno) : std::string()));
  return 1;
}

int run(int argc, char** argv) {
  // First, before any file is opened: a closed standard descriptor must not be reused.
  mvox::secure_standard_descriptors();
  // Before any thread exists: every thread must inherit the blocked interrupt signals.
  mvox::install_termination_handling();
  if (argc > 1 && argv[1][0] != '-') mvox::set_interrupt_subject(std::string("mvox ") + argv[1]);

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
  // Building a command's options costs more than most runs' own start-up (CLI11 makes an
  // object, names and checks for each): a run that names its command builds that one alone;
  // `mvox --help`, `--version` and a mistyped command build them all.
  const std::string named = argc > 1 ? argv[1] : "";
  const struct {
    const char* name;
    void (*add)(CLI::App&);
  } commands[] = {{"extract", [](CLI::App& a) { mvox::add_extract_command(a); }},
                  {"demo", mvox::add_demo_command},
                  {"phantom", mvox::add_phantom_command},
                  {"render", mvox::add_render_command}};
  bool one = false;
  for (const auto& command : commands) one = one || named == command.name;
  for (const auto& command : commands) {
    if (!one || named == command.name) command.add(app);
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // The message quotes the option's value, which may hold a newline like anything typed.
    mvox::print_message("error", e.what());
    std::fputs("Run 'mvox --help' or 'mvox COMMAND --help' for usage.\n", stderr);
    return 2;
  } catch (const mvox::UsageError& e) {
    mvox::print_message("error", e.what());
    std::fputs("Run 'mvox --help' or 'mvox COMMAND --help' for usage.\n", stderr);
    return 2;
  } catch (const mvox::Error& e) {
    return job_failure(e, 1);
  } catch (const std::invalid_argument& e) {
    return job_failure(e, 2);
  } catch (const std::bad_alloc&) {
    // Without this, the line would read "std::bad_alloc", naming neither input nor size.
    const std::size_t bytes = mvox::failed_allocation_bytes();
    return job_failure(
        mvox::Error(
            mvox::interrupt_subject(),
            "out of memory" +
                (bytes > 0 ? ": an allocation of " + mvox::memory_text(bytes) + " failed"
                           : std::string()) +
                // Only extract has a plan to show; render reads its mesh whole.
                (named == "extract" ? "; mvox extract --dry-run tells what a run needs" : "")),
        1);
  } catch (const std::exception& e) {
    return job_failure(e, 1);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return checked_standard_output(run(argc, argv)); }
