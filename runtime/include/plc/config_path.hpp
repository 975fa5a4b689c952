// Where a file named by a config is. A relative path written in a config
// file (libraries:, retain: file, hmi: key_file, a plugin's or device's
// file parameter such as gsdml: or pcap:) is taken from that config file's
// folder, so a cell finds its files wherever it is started from; a path
// given on a command line is taken from the current directory, as every
// tool does (docs/config.md, "Relative paths").
//
// None of these throws, whatever the path: the throwing overloads of
// std::filesystem end a tool with std::terminate on an empty path (the
// folder of a bare "cell.yaml" is ""), so they are not used here.
#pragma once

#include <optional>
#include <string>

namespace plc {

// The folder relative paths in `config_file` are taken from: its folder as
// written, "." for a bare file name ("cell.yaml"), "/" for "/cell.yaml".
[[nodiscard]] std::string config_folder(const std::string& config_file);

// `path` as written in a config whose folder is `folder`: an absolute or
// empty one as it is, a relative one under the folder. Lexical only (no
// file is looked at); "." components are dropped, ".." ones are kept (the
// kernel resolves them, through symbolic links as it should).
[[nodiscard]] std::string path_in_folder(const std::string& folder, const std::string& path);

// path_in_folder(config_folder(config_file), path).
[[nodiscard]] std::string config_relative_path(const std::string& config_file,
                                               const std::string& path);

// `path` made absolute against the current directory, lexically normal.
// nullopt, with the reason in `error`, for an empty path or when the
// current directory is gone.
[[nodiscard]] std::optional<std::string> absolute_path(const std::string& path, std::string& error);

// Why the file at `path` (a config, a command file) cannot be read, "" when
// it can: an empty path, no such file, a folder, not a regular file (a FIFO
// would hold the reader until something writes into it), no permission.
[[nodiscard]] std::string readable_file_problem(const std::string& path);

// Why a file cannot be written at `path` (an output named on a command
// line: --stats-json, --trace, --record), "" when it can: an empty path, a
// folder that does not exist, is not a folder or is not writable, a path
// that is a folder, an existing file that is not writable. Checked before a
// run starts, so that its results are not lost at the end.
[[nodiscard]] std::string writable_file_problem(const std::string& path);

}  // namespace plc
