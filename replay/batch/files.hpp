#pragma once
// The files of a plan folder: whole-file text and JSON with errors naming the file, absolute
// paths as a plan records them, and the stamps a task's result carries (UTC time, host).
// Shared by planning, running, task state and merging.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "core/result.hpp"

namespace orthosonar::batch {

// A file's whole content. Errors name the file.
Result<std::string> read_text(const std::string& path);
// Replaces `path` with `text`. Errors name the file.
Status write_text(const std::filesystem::path& path, const std::string& text);
// A JSON file; errors name the file (and say why it is not JSON).
Result<nlohmann::json> read_json_file(const std::string& path);

// `p` made absolute and lexically normal (as given when the working directory is unknown).
std::string absolute_path(const std::string& p);

// "2026-01-31T12:00:00Z", now.
std::string utc_now();
// This machine's host name.
std::string host_name();

}  // namespace orthosonar::batch
