// mvox-mpi: `mvox extract` on many processes, `mpirun -np R mvox-mpi extract INPUT... -o mesh`.
// Every rank parses the same options and opens the same input; the job
// (distributed_mesh_job.h) then runs on all of them, and the mesh they write together is the
// one `mvox extract` writes alone, byte for byte. Failures are agreed on (mpi_world.h): the
// lowest failing rank prints the one line, every rank exits with the same code as mvox would.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <new>
#include <stdexcept>
#include <string>

#include "cli/commands.h"
#include "error.h"
#include "message_line.h"
#include "mpi/distributed_mesh_job.h"
#include "mpi/mpi_world.h"
#include "pipeline/termination.h"
#include "write/standard_descriptors.h"

namespace {

int run(mvox::MpiWorld& world, int argc, char** argv) {
  CLI::App app{
      "mvox-mpi: mvox extract on many processes, one mesh file written together with MPI-IO, "
      "the same bytes as mvox extract.\nExample:\n"
      "  mpirun -np 4 mvox-mpi extract volume.raw --raw 512x512x2048:u16le -t 600 -o mesh.ply",
      "mvox-mpi"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "mvox-mpi 0.1.0");
  mvox::add_extract_command(app, [&world](mvox::SliceSource& source, const mvox::MeshJob& job) {
    mvox::run_distributed_mesh_job(source, job, world);
  });
  try {
    app.parse(argc, argv);
    return 0;
  } catch (const CLI::ParseError& e) {
    // Help, version and malformed options are the same on every rank: rank 0 speaks.
    if (world.rank() != 0) return e.get_exit_code() == 0 ? 0 : 2;
    if (e.get_exit_code() == 0) return app.exit(e);
    mvox::print_message("error", e.what());
    std::fputs("Run 'mvox-mpi extract --help' for usage.\n", stderr);
    return 2;
  }
}

// The exit code mvox gives a failure: 2 for a usage error, 1 for a failed job.
int exit_code_of(const std::exception_ptr& failure) {
  try {
    std::rethrow_exception(failure);
  } catch (const mvox::UsageError&) {
    return 2;
  } catch (const std::invalid_argument&) {
    return 2;
  } catch (...) {
    return 1;
  }
}

// The one line for a failure, as mvox words it.
std::string failure_line(const std::exception& e) {
  if (dynamic_cast<const std::bad_alloc*>(&e))
    return mvox::interrupt_subject() +
           ": out of memory; mvox-mpi extract --dry-run tells what a rank needs";
  return e.what();
}

}  // namespace

int main(int argc, char** argv) {
  mvox::secure_standard_descriptors();
  mvox::set_message_program("mvox-mpi");
  mvox::install_termination_handling();
  mvox::set_interrupt_subject("mvox-mpi extract");
  mvox::MpiWorld world(&argc, &argv, &exit_code_of);
  int code = 0;
  try {
    code = run(world, argc, argv);
  } catch (const mvox::OtherRankFailed& e) {
    code = e.exit_code;
  } catch (const std::exception& e) {
    // A rank that failed before the job began takes part in the others' first step, so that
    // they do not wait for it; of the ranks that failed, the lowest reports, and every rank
    // ends with its exit code.
    code = exit_code_of(std::current_exception());
    const bool report = world.joined() || world.fail_before_join(std::current_exception(), &code);
    if (report) mvox::print_message("error", failure_line(e));
  }
  // mpirun stops the other ranks when one fails; they have nothing more to say.
  if (code != 0) mvox::set_interrupts_quiet();
  return code;
}
