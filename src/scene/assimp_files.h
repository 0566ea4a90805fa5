// assimp's file access routed through SceneFiles, so that a load through assimp obeys the
// same rules as every other loader (LoadOptions): the scene file and every file an
// importer asks for (FBX/DAE side files, MD2 skins, ...) are checked with stat() before
// being opened, named files stay inside the scene's folder, and every byte counts against
// max_total_bytes. Private to src/scene (load_assimp.cpp); only built with assimp.
#pragma once

#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>

#include <string>
#include <vector>

#include "core/scene_files.h"

namespace multiray::detail {

// A read-only stream over bytes it owns. Written here rather than using assimp's
// MemoryIOStream, whose Read() divides by the element size unchecked.
class ByteStream : public Assimp::IOStream {
 public:
  explicit ByteStream(std::vector<unsigned char> bytes) : bytes_(std::move(bytes)) {}
  size_t Read(void* out, size_t size, size_t count) override;
  size_t Write(const void*, size_t, size_t) override { return 0; }
  aiReturn Seek(size_t offset, aiOrigin origin) override;
  size_t Tell() const override { return pos_; }
  size_t FileSize() const override { return bytes_.size(); }
  void Flush() override {}

 private:
  std::vector<unsigned char> bytes_;
  size_t pos_ = 0;
};

// Serves the scene file from the bytes already read (importers open it more than once:
// format detection, then the import) and every other file through SceneFiles::read().
// Refuses writing. `files` must outlive this object (the Importer owns and deletes it).
class SceneFileSystem : public Assimp::IOSystem {
 public:
  SceneFileSystem(SceneFiles* files, std::vector<unsigned char> scene_bytes)
      : files_(files), scene_bytes_(std::move(scene_bytes)) {}
  // stat() only: true for an existing regular file. Whether it may be read is decided
  // when it is opened.
  bool Exists(const char* path) const override;
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char* path, const char* mode = "rb") override;
  void Close(Assimp::IOStream* stream) override { delete stream; }

  // Why the first refused file was refused ("'a.bin' lies outside ..."), or "" if none
  // was: added to the error when the import then fails.
  const std::string& first_refusal() const { return first_refusal_; }

 private:
  SceneFiles* files_;
  std::vector<unsigned char> scene_bytes_;
  std::string first_refusal_;
};

// assimp's OFF reader allocates the vertex and face arrays its header announces before
// reading a line: a 310-byte file claiming 353535235358 vertices (assimp-testmodels'
// invalid/OutOfMemory.off) took 16 GB. Reads the counts as assimp does (decimal digits
// wrapping at 2^32, after an optional [ST][C][N][4][n]OFF keyword and dimension) and
// throws InputError "<path>: ..." when either exceeds the bytes the file has, since every
// vertex and face takes a line of its own.
void check_off_counts(const std::string& path, const std::string& text);

}  // namespace multiray::detail
