#pragma once
// How mvox ends when it is stopped from outside: by SIGINT, SIGTERM, SIGHUP or another signal
// that would end it (SIGQUIT, SIGUSR1, SIGALRM, SIGXCPU: an interrupt), or
// by a reader that closes its end of an output pipe. Either way no output file and no temporary
// is left behind, and a previous file at an output's path stays as it was.
//
// INTERRUPTS. install_termination_handling() blocks these signals in the calling thread, so
// in every thread started after it (they inherit the mask), and waits for them with sigwait() on
// a thread of its own. When one comes, that thread deletes every registered temporary, prints
// one line ("mvox: error: mesh.ply: interrupted by SIGINT") and ends the process with
// _exit(128 + signal), 130 for SIGINT, as shells report a process killed by the signal.
//
// Why not a flag polled between slices: the reading thread may sit in read() on a slow disk or a
// FIFO for as long as the writer likes, or in OpenCV's decoder, so the job cannot be relied on
// to notice. Why not an ordinary signal handler that unlinks: a temporary's name is chosen by
// mkostemp() as it creates the file, so a handler could run between the creation and the
// registration and miss the file, and a handler may not take a lock to close that gap. The
// waiting thread is ordinary code: it takes the registry's lock, which is also held while a
// temporary is created and registered, and while it is renamed onto its target and forgotten.
// So every temporary it can see is either not yet created, registered, or already published.
// Signals that were ignored when mvox started (nohup, a background job of a script) stay
// ignored, as the shell intended.
//
// CLOSED PIPES. SIGPIPE is ignored, so a write to a pipe whose reader has gone fails with EPIPE
// like any other write error: the job unwinds, and its destructors delete the temporaries.
// OutputFile notes it (note_broken_pipe), and main then ends quietly, as if killed by SIGPIPE:
// no message and exit status 141 in the shell, which is what `cat`, `grep` or `sort` give in
// `... | head`; the reader asked for no more, so an error line would only be noise.
//
// FILE-SIZE LIMITS. SIGXFSZ is ignored too: a write beyond `ulimit -f` then fails with EFBIG
// ("File too large") and unwinds like a full disk, instead of killing mvox mid-write.
//
// The registry works without install_termination_handling() too (tests, library users): it
// then only records, and signals keep their default actions.
#include <cstddef>
#include <string>
#include <vector>

namespace mvox {

// Call first in main, before any thread is started. Idempotent.
void install_termination_handling();

// OUTPUTS IN PROGRESS -------------------------------------------------------------------------
// Every OutputFile is recorded from its creation until it is published or discarded. Records
// have ids > 0. All functions are thread-safe.

// Creates a file from `name_template` (mkostemp with O_CLOEXEC: the trailing XXXXXX are replaced
// in place) as the temporary of the output named `target` in messages, recorded so that an
// interrupt deletes it. Returns the descriptor, or -1 with errno set; *id gets the record.
int create_output_temporary(char* name_template, const std::string& target, int* id);

// A folder from `name_template` (mkdtemp), recorded as create_output_temporary records a file:
// an interrupt, or discard_output(), removes it with everything in it; publish_output_temporary
// renames it onto its target. For outputs that are folders of files (mvox phantom's stacks).
// False with errno set when it cannot be made.
bool create_output_temporary_directory(char* name_template, const std::string& target, int* id);

// Records an output written directly (standard output, a device, a pipe): nothing to delete,
// but an interrupt names it. Returns the record's id.
int register_direct_output(const std::string& target);

// Renames the recorded temporary onto `target_path` and forgets the record, as one step an
// interrupt cannot split. Returns 0, or the errno of rename() (the record is then kept).
int publish_output_temporary(int id, const std::string& target_path);

// One output to publish: the record of its temporary and the path it replaces.
struct Publication {
  int id = 0;
  std::string target_path;
};

// Replaces every target by its record's temporary, all or none, as one step an interrupt cannot
// split, and forgets the records. An existing target is swapped with its temporary
// (renameat2 RENAME_EXCHANGE), so that until all have succeeded each previous file is still at
// hand under the temporary's name; a new target is created without replacing anything
// (RENAME_NOREPLACE). When a step fails, the steps already made are reversed and the previous
// files are back in place; on success they are deleted. Returns 0, or the errno of the step
// that failed, with *failed_index set to its position in `items` (the records are then kept).
// On a file system that cannot exchange or refuse to replace (EINVAL: some network file
// systems), a plain rename is used for that target, which cannot be reversed.
int publish_output_temporaries(const std::vector<Publication>& items, std::size_t* failed_index);

// Deletes the record's temporary, if it has one and it was not published, and forgets it.
void discard_output(int id);

// Creates a file from `name_template` (as create_output_temporary) and unlinks it at once, as
// one step an interrupt cannot split: a nameless scratch file. Returns the descriptor or -1.
int create_nameless_temporary(char* name_template);

// From here on an interrupt still deletes the temporaries and exits, without a line: for a
// process whose failure has been reported already, by another (the ranks of mvox-mpi, which
// mpirun may stop once one of them has failed).
void set_interrupts_quiet();

// What an interrupt names when no output is in progress, e.g. the input being opened.
void set_interrupt_subject(const std::string& subject);
// The subject last set ("mvox" before any): what a failure without a subject of its own, such
// as running out of memory, names.
std::string interrupt_subject();

// While one exists, an interrupt waits: for steps that must not be split, such as publishing
// several outputs that appear together. Keep the scope short; it may nest.
class InterruptsDeferred {
 public:
  InterruptsDeferred();
  ~InterruptsDeferred();
  InterruptsDeferred(const InterruptsDeferred&) = delete;
  InterruptsDeferred& operator=(const InterruptsDeferred&) = delete;
};

// CLOSED PIPES --------------------------------------------------------------------------------

// Called by writers when write() failed with EPIPE.
void note_broken_pipe();
bool broken_pipe_noted();

// Ends the process as SIGPIPE's default action would: no message, status 141 in the shell.
[[noreturn]] void exit_for_broken_pipe();

}  // namespace mvox
