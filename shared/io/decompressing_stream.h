#ifndef FLEETMAP_SHARED_IO_DECOMPRESSING_STREAM_H_
#define FLEETMAP_SHARED_IO_DECOMPRESSING_STREAM_H_

#include <cstdio>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace fleetmap {

// Reads a text file line by line, decompressing gzip or bzip2 on the fly. The format is chosen
// from the first bytes (gzip 1f 8b, bzip2 "BZh"), not from the file name, so a renamed file
// still reads. Only a bounded window of the file is held in memory.
class DecompressingStream {
 public:
  enum class Format { kPlain, kGzip, kBzip2 };

  // Lines longer than this are refused as corrupt instead of growing the buffer without bound.
  static constexpr size_t kMaxLineBytes = size_t{8} << 20;

  // Returns nullptr and fills `error` when the file cannot be opened.
  static std::unique_ptr<DecompressingStream> Open(const std::string& path, std::string* error);
  virtual ~DecompressingStream();

  // Sets `line` to the next line without its '\n' (valid until the next call). Returns false at
  // the end of the data or on an error (then error() is non-empty).
  bool NextLine(std::string_view* line);
  const std::string& error() const { return error_; }
  Format format() const { return format_; }

 protected:
  DecompressingStream(std::FILE* file, Format format);
  // Fills up to `size` bytes of decompressed data; returns 0 at the end, -1 on error (with
  // error_ set).
  virtual long Read(char* data, size_t size) = 0;
  // Reads raw (compressed) bytes from the file; returns 0 at the end, -1 on error.
  long ReadRaw(char* data, size_t size);

  std::FILE* file_;
  std::string error_;

 private:
  bool Fill();

  Format format_;
  std::vector<char> buffer_;
  size_t begin_ = 0;
  size_t end_ = 0;
  bool at_end_ = false;
};

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_IO_DECOMPRESSING_STREAM_H_
