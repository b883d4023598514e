#pragma once
// Heap storage for an engine workspace, aligned as the engine requires. The core never
// allocates; hosts, tests and the simulator allocate its workspace once, up front, with this.
#include <cstddef>
#include <memory>

#include "mvox/engine.h"

namespace mvox {

class WorkspaceBuffer {
 public:
  explicit WorkspaceBuffer(std::size_t bytes)
      : blocks_(new Block[bytes / sizeof(Block) + 1]),
        bytes_((bytes / sizeof(Block) + 1) * sizeof(Block)) {}
  void* data() { return blocks_.get(); }
  std::size_t bytes() const { return bytes_; }

 private:
  struct alignas(kWorkspaceAlignment) Block {
    unsigned char bytes[kWorkspaceAlignment];
  };
  std::unique_ptr<Block[]> blocks_;
  std::size_t bytes_;
};

}  // namespace mvox
