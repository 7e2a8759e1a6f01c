#include "shared/io/decompressing_stream.h"

#include <bzlib.h>
#include <zlib.h>

#include <cerrno>
#include <cstring>

namespace fleetmap {
namespace {

constexpr size_t kChunkBytes = size_t{1} << 20;
constexpr size_t kRawChunkBytes = size_t{256} << 10;

class PlainStream : public DecompressingStream {
 public:
  PlainStream(std::FILE* file, Format format) : DecompressingStream(file, format) {}

 protected:
  long Read(char* data, size_t size) override { return ReadRaw(data, size); }
};

// Both compressors allow several compressed streams back to back in one file (pigz, pbzip2);
// the decoders below restart after each stream end while input remains.
class GzipStream : public DecompressingStream {
 public:
  GzipStream(std::FILE* file, Format format)
      : DecompressingStream(file, format), in_(kRawChunkBytes) {
    // 15 + 32: any window size, gzip or zlib header detected automatically.
    ok_ = inflateInit2(&z_, 15 + 32) == Z_OK;
  }
  ~GzipStream() override { inflateEnd(&z_); }

 protected:
  long Read(char* data, size_t size) override {
    if (!ok_) return Fail("cannot initialise zlib");
    z_.next_out = reinterpret_cast<Bytef*>(data);
    z_.avail_out = static_cast<uInt>(size);
    while (z_.avail_out == size) {
      if (z_.avail_in == 0 && !input_done_) {
        const long n = ReadRaw(in_.data(), in_.size());
        if (n < 0) return -1;
        if (n == 0) input_done_ = true;
        z_.next_in = reinterpret_cast<Bytef*>(in_.data());
        z_.avail_in = static_cast<uInt>(n);
      }
      if (z_.avail_in == 0 && input_done_) {
        if (in_stream_) return Fail("gzip data ends early (truncated file?)");
        return 0;
      }
      in_stream_ = true;
      const int status = inflate(&z_, Z_NO_FLUSH);
      if (status == Z_STREAM_END) {
        in_stream_ = false;
        inflateReset(&z_);
      } else if (status != Z_OK && status != Z_BUF_ERROR) {
        return Fail(std::string("corrupt gzip data: ") + (z_.msg ? z_.msg : "unknown error"));
      }
    }
    return static_cast<long>(size - z_.avail_out);
  }

 private:
  long Fail(const std::string& message) {
    error_ = message;
    return -1;
  }

  z_stream z_{};
  std::vector<char> in_;
  bool ok_ = false;
  bool input_done_ = false;
  bool in_stream_ = false;
};

class Bzip2Stream : public DecompressingStream {
 public:
  Bzip2Stream(std::FILE* file, Format format)
      : DecompressingStream(file, format), in_(kRawChunkBytes) {
    ok_ = BZ2_bzDecompressInit(&bz_, 0, 0) == BZ_OK;
  }
  ~Bzip2Stream() override {
    if (ok_) BZ2_bzDecompressEnd(&bz_);
  }

 protected:
  long Read(char* data, size_t size) override {
    if (!ok_) return Fail("cannot initialise libbz2");
    bz_.next_out = data;
    bz_.avail_out = static_cast<unsigned>(size);
    while (bz_.avail_out == size) {
      if (bz_.avail_in == 0 && !input_done_) {
        const long n = ReadRaw(in_.data(), in_.size());
        if (n < 0) return -1;
        if (n == 0) input_done_ = true;
        bz_.next_in = in_.data();
        bz_.avail_in = static_cast<unsigned>(n);
      }
      if (bz_.avail_in == 0 && input_done_) {
        if (in_stream_) return Fail("bzip2 data ends early (truncated file?)");
        return 0;
      }
      in_stream_ = true;
      const int status = BZ2_bzDecompress(&bz_);
      if (status == BZ_STREAM_END) {
        in_stream_ = false;
        // Keep the unread input: it may hold the next stream.
        char* next_in = bz_.next_in;
        const unsigned avail_in = bz_.avail_in;
        char* next_out = bz_.next_out;
        const unsigned avail_out = bz_.avail_out;
        BZ2_bzDecompressEnd(&bz_);
        bz_ = bz_stream{};
        ok_ = BZ2_bzDecompressInit(&bz_, 0, 0) == BZ_OK;
        if (!ok_) return Fail("cannot initialise libbz2");
        bz_.next_in = next_in;
        bz_.avail_in = avail_in;
        bz_.next_out = next_out;
        bz_.avail_out = avail_out;
      } else if (status != BZ_OK) {
        return Fail("corrupt bzip2 data (libbz2 error " + std::to_string(status) + ")");
      }
    }
    return static_cast<long>(size - bz_.avail_out);
  }

 private:
  long Fail(const std::string& message) {
    error_ = message;
    return -1;
  }

  bz_stream bz_{};
  std::vector<char> in_;
  bool ok_ = false;
  bool input_done_ = false;
  bool in_stream_ = false;
};

}  // namespace

std::unique_ptr<DecompressingStream> DecompressingStream::Open(const std::string& path,
                                                               std::string* error) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) {
    if (error) *error = path + ": cannot open: " + std::strerror(errno);
    return nullptr;
  }
  unsigned char magic[3] = {0, 0, 0};
  const size_t got = std::fread(magic, 1, sizeof(magic), file);
  Format format = Format::kPlain;
  if (got >= 2 && magic[0] == 0x1f && magic[1] == 0x8b) {
    format = Format::kGzip;
  } else if (got == 3 && magic[0] == 'B' && magic[1] == 'Z' && magic[2] == 'h') {
    format = Format::kBzip2;
  }
  if (std::fseek(file, 0, SEEK_SET) != 0) {
    if (error) *error = path + ": cannot rewind (not a regular file?)";
    std::fclose(file);
    return nullptr;
  }
  switch (format) {
    case Format::kGzip:
      return std::unique_ptr<DecompressingStream>(new GzipStream(file, format));
    case Format::kBzip2:
      return std::unique_ptr<DecompressingStream>(new Bzip2Stream(file, format));
    case Format::kPlain:
      break;
  }
  return std::unique_ptr<DecompressingStream>(new PlainStream(file, format));
}

DecompressingStream::DecompressingStream(std::FILE* file, Format format)
    : file_(file), format_(format), buffer_(kChunkBytes) {}

DecompressingStream::~DecompressingStream() { std::fclose(file_); }

long DecompressingStream::ReadRaw(char* data, size_t size) {
  const size_t n = std::fread(data, 1, size, file_);
  if (n == 0 && std::ferror(file_)) {
    error_ = std::string("read error: ") + std::strerror(errno);
    return -1;
  }
  return static_cast<long>(n);
}

// Moves the unread tail to the front and reads more after it, growing the buffer when one line
// fills it. Returns false when no byte could be added (end of data or error).
bool DecompressingStream::Fill() {
  if (at_end_ || !error_.empty()) return false;
  if (begin_ > 0) {
    std::memmove(buffer_.data(), buffer_.data() + begin_, end_ - begin_);
    end_ -= begin_;
    begin_ = 0;
  }
  if (end_ == buffer_.size()) {
    if (buffer_.size() >= kMaxLineBytes) {
      error_ = "line longer than " + std::to_string(kMaxLineBytes >> 20) + " MB (corrupt file?)";
      return false;
    }
    buffer_.resize(std::min(buffer_.size() * 2, kMaxLineBytes));
  }
  const long n = Read(buffer_.data() + end_, buffer_.size() - end_);
  if (n < 0) return false;
  if (n == 0) {
    at_end_ = true;
    return false;
  }
  end_ += static_cast<size_t>(n);
  return true;
}

bool DecompressingStream::NextLine(std::string_view* line) {
  size_t searched = begin_;
  while (true) {
    const void* newline = std::memchr(buffer_.data() + searched, '\n', end_ - searched);
    if (newline != nullptr) {
      const size_t at = static_cast<size_t>(static_cast<const char*>(newline) - buffer_.data());
      *line = std::string_view(buffer_.data() + begin_, at - begin_);
      begin_ = at + 1;
      return true;
    }
    const size_t unread_searched = end_ - begin_;
    if (!Fill()) {
      if (!error_.empty() || begin_ == end_) return false;
      // The last line of a file without a final newline.
      *line = std::string_view(buffer_.data() + begin_, end_ - begin_);
      begin_ = end_;
      return true;
    }
    searched = begin_ + unread_searched;
  }
}

}  // namespace fleetmap
