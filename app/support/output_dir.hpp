// app/support/output_dir.hpp - checking an output folder before a session spends any time on it.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace tridex::app {

/// Creates `dir` (and its parents) when missing and proves it writable by creating and removing a small probe
/// file in it. Throws tridex::Error "<flag> <dir>: <reason>" (e.g. "--out /dev/full: not a folder", "--out /ro:
/// cannot write there: Read-only file system") so that a bad output location is refused before the session runs.
/// Removes the temporary files that writers killed in an earlier run left there (remove_stale_temp_files).
void prepare_output_dir(const std::string& dir, const std::string& flag);

/// The folders prepare_output_dir and check_output_file created since forget_created_folders() (the outermost
/// first): remove_created_folders_if_empty() removes those still empty, innermost first, so a command that fails
/// before writing anything leaves no empty --out folder behind. Folders that held something before, or were written
/// into, stay. One thread (a command's). Never throws.
void forget_created_folders();
/// See forget_created_folders(). Returns how many folders were removed.
std::size_t remove_created_folders_if_empty();

/// Removes, from `dir` (not its sub-folders), the regular files named "<name>.tmp-<pid>" (core/atomic_file.hpp's
/// temporary files) whose process no longer runs (kill(pid, 0) fails with ESRCH): what a run killed while writing
/// left behind. Files of running processes and other names are kept. Returns how many were removed; never throws.
std::size_t remove_stale_temp_files(const std::string& dir);

/// Checks that a file can be created at `path` (its folder exists or can be made, and a probe file can be written
/// beside it; the file itself is not created). Throws tridex::Error "<flag> <path>: <reason>".
void check_output_file(const std::string& path, const std::string& flag);

/// A file a command reads or writes, and what names it ("--save", "--out's report.json").
struct NamedFile {
    std::string what;
    std::string path;
};

/// Refuses a command whose outputs would overwrite each other or one of its inputs: two `outputs` naming the same
/// file, or an output naming one of `inputs` (a session that saves over the model it started from also leaves its
/// journal and recording unusable, since they name that model by its bytes). Paths are compared after
/// std::filesystem::weakly_canonical, so "out/../a.tdx" and "a.tdx" match; entries with an empty path are skipped.
/// Throws tridex::Error "<what> <path>: is also <other's what>; ...".
void check_distinct_files(const std::vector<NamedFile>& outputs, const std::vector<NamedFile>& inputs = {});

/// A session's outputs written each on its own, so that one that fails (a full disk, a removed folder) costs no
/// other: a failed write is said at once on stderr in one line ("tridex: <its error>") and the next is still tried.
class OutputWrites {
public:
    /// Runs `write`, which writes the file `path` and throws tridex::Error naming it on failure; true when it wrote.
    /// Errors other than tridex::Error propagate.
    bool attempt(const std::string& path, const std::function<void()>& write);
    /// The files written so far, in order.
    const std::vector<std::string>& written() const { return written_; }
    /// The errors of the writes that failed, in order.
    const std::vector<std::string>& failures() const { return failures_; }
    /// Throws tridex::Error "N of M outputs were not written (each said above); the other outputs and report.json
    /// were written to <out_dir>: a, b" (or "nothing was written") when any write failed.
    void finish(const std::string& out_dir) const;

private:
    std::vector<std::string> written_;
    std::vector<std::string> failures_;
};

}  // namespace tridex::app
