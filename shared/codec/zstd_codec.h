#ifndef FLEETMAP_SHARED_CODEC_ZSTD_CODEC_H_
#define FLEETMAP_SHARED_CODEC_ZSTD_CODEC_H_

#include <cstddef>
#include <string>

namespace fleetmap {

// Compresses `size` bytes into one zstd frame that records its content size, so a reader can
// check the size before allocating. Level 1 is fast enough for per-request use.
std::string ZstdCompress(const void* data, size_t size, int level = 1);

// Decompresses one zstd frame into `out`. Refuses (false + `error`) corrupt input, frames that
// do not declare their content size, and frames whose content is not exactly `expected_size`
// bytes, so a hostile frame can never make us allocate more than the caller allowed.
bool ZstdDecompress(const std::string& compressed, size_t expected_size, std::string* out,
                    std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_CODEC_ZSTD_CODEC_H_
