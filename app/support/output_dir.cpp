// app/support/output_dir.cpp - up-front checks of output locations.
#include "app/support/output_dir.hpp"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/error.hpp"

namespace tridex::app {

namespace {

namespace fs = std::filesystem;

// Writes, flushes and removes a probe file in `dir`; "" on success, else the reason.
std::string probe(const fs::path& dir) {
    const fs::path p = dir / (".tridex-probe-" + std::to_string(::getpid()));
    std::FILE* f = std::fopen(p.c_str(), "wb");
    if (!f) return std::string("cannot write there: ") + std::strerror(errno);
    const char bytes[64] = {};
    bool ok = std::fwrite(bytes, 1, sizeof bytes, f) == sizeof bytes && std::fflush(f) == 0;
    const int err = errno;
    ok = std::fclose(f) == 0 && ok;
    std::remove(p.c_str());
    return ok ? "" : std::string("cannot write there: ") + std::strerror(err ? err : EIO);
}

// The path as check_distinct_files compares it.
fs::path comparable(const std::string& path) {
    std::error_code ec;
    fs::path p = fs::weakly_canonical(fs::absolute(fs::path(path), ec), ec);
    return ec ? fs::absolute(fs::path(path)).lexically_normal() : p;
}

}  // namespace

void check_distinct_files(const std::vector<NamedFile>& outputs, const std::vector<NamedFile>& inputs) {
    std::vector<std::pair<fs::path, const NamedFile*>> seen;
    for (const NamedFile& f : inputs)
        if (!f.path.empty()) seen.emplace_back(comparable(f.path), &f);
    const std::size_t n_inputs = seen.size();
    for (const NamedFile& f : outputs) {
        if (f.path.empty()) continue;
        const fs::path p = comparable(f.path);
        for (std::size_t k = 0; k < seen.size(); ++k)
            if (seen[k].first == p)
                throw Error(f.what + " " + f.path + ": is also " + seen[k].second->what +
                            (k < n_inputs ? ", which the session reads: writing it would lose it; name another file"
                                          : "; each output needs its own file"));
        seen.emplace_back(p, &f);
    }
}

std::size_t remove_stale_temp_files(const std::string& dir) {
    std::size_t removed = 0;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        const std::size_t at = name.rfind(".tmp-");
        if (at == std::string::npos || at == 0 || at + 5 >= name.size()) continue;
        const std::string pid_text = name.substr(at + 5);
        if (pid_text.size() > 9 || pid_text.find_first_not_of("0123456789") != std::string::npos) continue;
        const long pid = std::stol(pid_text);
        std::error_code e2;
        if (pid <= 0 || !it->is_regular_file(e2)) continue;
        if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // still running (or not ours)
        if (fs::remove(it->path(), e2)) ++removed;
    }
    return removed;
}

namespace {

std::vector<fs::path>& created_folders() {
    static std::vector<fs::path> folders;
    return folders;
}

// fs::create_directories, remembering each folder it makes (outermost first).
void create_folders(const fs::path& d, std::error_code& ec) {
    std::vector<fs::path> missing;
    for (fs::path p = fs::absolute(d, ec).lexically_normal(); !p.empty() && !fs::exists(p, ec); p = p.parent_path()) {
        missing.push_back(p);
        if (p == p.parent_path()) break;
    }
    fs::create_directories(d, ec);
    if (ec) return;
    for (auto it = missing.rbegin(); it != missing.rend(); ++it) created_folders().push_back(*it);
}

}  // namespace

void forget_created_folders() { created_folders().clear(); }

std::size_t remove_created_folders_if_empty() {
    std::size_t removed = 0;
    std::vector<fs::path>& folders = created_folders();
    for (auto it = folders.rbegin(); it != folders.rend(); ++it) {
        std::error_code ec;
        if (fs::is_directory(*it, ec) && fs::is_empty(*it, ec) && fs::remove(*it, ec)) ++removed;
    }
    folders.clear();
    return removed;
}

void prepare_output_dir(const std::string& dir, const std::string& flag) {
    if (dir.empty()) throw Error(flag + ": the output folder must not be empty");
    const fs::path d(dir);
    std::error_code ec;
    if (fs::exists(d, ec) && !fs::is_directory(d, ec)) throw Error(flag + " " + dir + ": not a folder");
    create_folders(d, ec);
    if (ec) throw Error(flag + " " + dir + ": cannot create the folder: " + ec.message());
    const std::string why = probe(d);
    if (!why.empty()) throw Error(flag + " " + dir + ": " + why);
    (void)remove_stale_temp_files(dir);
}

void check_output_file(const std::string& path, const std::string& flag) {
    if (path.empty()) throw Error(flag + ": the file name must not be empty");
    const fs::path p(path);
    std::error_code ec;
    if (fs::is_directory(p, ec)) throw Error(flag + " " + path + ": is a folder, not a file");
    if (fs::exists(p, ec) && !fs::is_regular_file(p, ec)) {
        // A device such as /dev/full: try to write to it as the session would.
        std::FILE* f = std::fopen(p.c_str(), "ab");
        if (!f) throw Error(flag + " " + path + ": cannot write: " + std::strerror(errno));
        const bool ok = std::fputc(0, f) != EOF && std::fflush(f) == 0;
        const int err = errno;
        std::fclose(f);
        if (!ok) throw Error(flag + " " + path + ": cannot write: " + std::strerror(err ? err : EIO));
        return;
    }
    const fs::path parent = p.has_parent_path() ? p.parent_path() : fs::path(".");
    create_folders(parent, ec);
    if (ec) throw Error(flag + " " + path + ": cannot create its folder: " + ec.message());
    const std::string why = probe(parent);
    if (!why.empty()) throw Error(flag + " " + path + ": " + why);
}

bool OutputWrites::attempt(const std::string& path, const std::function<void()>& write) {
    try {
        write();
    } catch (const Error& e) {
        std::fprintf(stderr, "tridex: %s\n", e.what());
        failures_.push_back(e.what());
        return false;
    }
    written_.push_back(path);
    return true;
}

void OutputWrites::finish(const std::string& out_dir) const {
    if (failures_.empty()) return;
    std::fflush(stdout);  // the session's summary first, then this line
    std::string written;
    bool report = false;
    for (const std::string& w : written_) {
        written += (written.empty() ? "" : ", ") + w;
        report = report || std::filesystem::path(w).filename() == "report.json";
    }
    const std::string n = std::to_string(failures_.size()) + " of " + std::to_string(failures_.size() + written_.size());
    throw Error(n + " outputs were not written (each said above); " +
                (written.empty() ? std::string("nothing was written")
                                 : std::string("the other outputs") + (report ? " and report.json" : "") +
                                       " were written to " + out_dir + ": " + written));
}

}  // namespace tridex::app
