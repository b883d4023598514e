#pragma once
// What the engines of every label emit, kept in one nameless scratch file as it streams, so that
// each label's mesh file can be written whole afterwards, one at a time: memory holds one
// engine per label present in the current slices and one write buffer, never one mesh writer
// per label (mvox extract --labels).
//
// A label's surface may come from several engine sessions (the label leaves the slices and comes
// back); each session numbers its vertices from 0, and the spool moves its polygons' indices on
// by the vertices the label had before, so that the replay is one mesh, as one engine over that
// label's mask would emit it.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "error.h"
#include "mvox/polygon_sink.h"
#include "write/scratch_file.h"

namespace mvox {

class LabelSpool {
 public:
  // The scratch file is created in `directory`; messages name `subject`.
  LabelSpool(const std::string& directory, const std::string& subject);
  ~LabelSpool();
  LabelSpool(const LabelSpool&) = delete;
  LabelSpool& operator=(const LabelSpool&) = delete;

  // A sink for one engine session of `label`, starting now: polygons' indices are moved by the
  // vertices recorded for the label so far. Borrowed from the spool (valid until it is gone).
  PolygonSink& session(std::uint32_t label);

  struct LabelCounts {
    std::uint64_t vertices = 0;
    std::uint64_t polygons = 0;
    std::uint64_t sessions = 0;  // engines that extracted it: one more each time it came back
  };
  // Every label recorded, increasing, with its counts.
  const std::map<std::uint32_t, LabelCounts>& labels() const { return counts_; }
  // The bytes the spool took on disk, and the record offsets it keeps in memory.
  std::uint64_t bytes_written() const { return file_.bytes_written(); }
  std::uint64_t index_bytes() const { return index_bytes_; }

  // The first error a session kept (its engine then saw sink_refused), or nullptr.
  const Error* error() const;

  // Replays `label`'s records, in order, into `sink`. Throws mvox::Error on a read error;
  // returns the sink's status for the first call it refused (Status::ok if none).
  Status replay(std::uint32_t label, PolygonSink& sink);

 private:
  class Session;
  enum class Kind : std::uint8_t { vertices, polygons, geometry };
  void record(std::uint32_t label, Kind kind, const void* items, std::size_t item_bytes,
              std::size_t count);

  ScratchFile file_;
  std::string file_subject_;
  std::map<std::uint32_t, LabelCounts> counts_;
  std::map<std::uint32_t, std::vector<std::uint64_t>> records_;  // offsets, per label
  std::map<std::uint32_t, std::unique_ptr<Session>> sessions_;
  std::uint64_t index_bytes_ = 0;
  std::vector<unsigned char> read_buffer_;
  std::vector<Polygon> moved_;  // a session's polygon batch with its indices moved
};

}  // namespace mvox
