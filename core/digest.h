#pragma once
// SHA-256 and HMAC-SHA-256 (OpenSSL), as lower-case hex: the session log's hash chain and its
// keyed seals (docs/log-schema.md). ContentHash (FNV) stays the cache key: it is fast and only has
// to tell versions apart, not resist a forger.
#include <string>
#include <string_view>

namespace fovlab {

// SHA-256 of the concatenated parts.
std::string sha256_hex(std::string_view first, std::string_view second = {});

// HMAC-SHA-256 of `message` under `key`.
std::string hmac_sha256_hex(std::string_view key, std::string_view message);

}  // namespace fovlab
