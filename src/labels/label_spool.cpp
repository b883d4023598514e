#include "labels/label_spool.h"

#include <cstring>
#include <new>
#include <optional>

#include "error.h"

namespace mvox {

// One session's sink: records the engine's calls under its label.
class LabelSpool::Session final : public PolygonSink {
 public:
  Session(LabelSpool& spool, std::uint32_t label) : spool_(spool), label_(label) {}

  void start(std::uint64_t base) { base_ = static_cast<std::uint32_t>(base); }

  Status consume_vertices(const Vertex* vertices, std::size_t count) override {
    return guarded([&] {
      spool_.record(label_, Kind::vertices, vertices, sizeof(Vertex), count);
      spool_.counts_[label_].vertices += count;
    });
  }
  Status consume_polygons(const Polygon* polygons, std::size_t count) override {
    return guarded([&] {
      // Indices modulo 2^32, as polygons carry them (mvox/mesh.h): the move wraps with them.
      // One buffer for every session: a label map may have a hundred thousand labels.
      std::vector<Polygon>& moved = spool_.moved_;
      moved.assign(polygons, polygons + count);
      if (base_ != 0)
        for (Polygon& polygon : moved)
          for (int k = 0; k < polygon.vertex_count; ++k) polygon.vertices[k] += base_;
      spool_.record(label_, Kind::polygons, moved.data(), sizeof(Polygon), count);
      spool_.counts_[label_].polygons += count;
    });
  }
  Status consume_polygon_geometry(const PolygonGeometry* polygons, std::size_t count) override {
    return guarded(
        [&] { spool_.record(label_, Kind::geometry, polygons, sizeof(PolygonGeometry), count); });
  }

  // The engine is built without exceptions: an error is kept for the job to throw.
  const Error* error() const { return error_ ? &*error_ : nullptr; }

 private:
  template <class Body>
  Status guarded(Body&& body) {
    if (error_) return Status::sink_refused;
    try {
      body();
      return Status::ok;
    } catch (const Error& error) {
      error_ = error;
    } catch (const std::bad_alloc&) {
      error_ = Error(spool_.file_subject_, "out of memory");
    }
    return Status::sink_refused;
  }

  LabelSpool& spool_;
  std::uint32_t label_;
  std::uint32_t base_ = 0;
  std::optional<Error> error_;
};

LabelSpool::LabelSpool(const std::string& directory, const std::string& subject)
    : file_(directory, subject), file_subject_(subject) {}

LabelSpool::~LabelSpool() = default;

PolygonSink& LabelSpool::session(std::uint32_t label) {
  std::unique_ptr<Session>& session = sessions_[label];
  if (!session) session = std::make_unique<Session>(*this, label);
  LabelCounts& counts = counts_[label];
  session->start(counts.vertices);
  ++counts.sessions;
  return *session;
}

const Error* LabelSpool::error() const {
  for (const auto& [label, session] : sessions_)
    if (session->error()) return session->error();
  return nullptr;
}

void LabelSpool::record(std::uint32_t label, Kind kind, const void* items, std::size_t item_bytes,
                        std::size_t count) {
  std::vector<std::uint64_t>& offsets = records_[label];
  if (offsets.capacity() == offsets.size()) index_bytes_ += offsets.size() * sizeof(std::uint64_t);
  offsets.push_back(file_.bytes_written());
  unsigned char head[5];
  head[0] = static_cast<unsigned char>(kind);
  const auto items_count = static_cast<std::uint32_t>(count);
  std::memcpy(head + 1, &items_count, 4);
  file_.write(head, sizeof head);
  file_.write(items, item_bytes * count);
}

Status LabelSpool::replay(std::uint32_t label, PolygonSink& sink) {
  const auto found = records_.find(label);
  if (found == records_.end()) return Status::ok;
  for (const std::uint64_t offset : found->second) {
    unsigned char head[5];
    file_.read_at(offset, head, sizeof head);
    std::uint32_t count;
    std::memcpy(&count, head + 1, 4);
    const auto kind = static_cast<Kind>(head[0]);
    const std::size_t item_bytes = kind == Kind::vertices   ? sizeof(Vertex)
                                   : kind == Kind::polygons ? sizeof(Polygon)
                                                            : sizeof(PolygonGeometry);
    read_buffer_.resize(item_bytes * count);
    file_.read_at(offset + sizeof head, read_buffer_.data(), read_buffer_.size());
    Status status = Status::ok;
    switch (kind) {
      case Kind::vertices:
        status = sink.consume_vertices(reinterpret_cast<const Vertex*>(read_buffer_.data()), count);
        break;
      case Kind::polygons:
        status =
            sink.consume_polygons(reinterpret_cast<const Polygon*>(read_buffer_.data()), count);
        break;
      case Kind::geometry:
        status = sink.consume_polygon_geometry(
            reinterpret_cast<const PolygonGeometry*>(read_buffer_.data()), count);
        break;
    }
    if (status != Status::ok) return status;
  }
  return Status::ok;
}

}  // namespace mvox
