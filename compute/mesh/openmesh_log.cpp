// compute/mesh/openmesh_log.cpp - capturing OpenMesh's global log streams.
#include "compute/mesh/openmesh_log.hpp"

#include <iostream>

namespace tridex::compute {
namespace {

/// The one buffer OpenMesh's log streams write into, connected on first use and never disconnected: OpenMesh's
/// mostream::disconnect drops the target it removes without freeing it, so connecting and disconnecting around
/// every capture lost memory on every mesh read or written. The standard streams are detached then, once (the
/// targets OpenMesh made for them at its start-up are lost once). Streams stay disabled between captures.
std::ostringstream& capture_buffer(const std::vector<OpenMesh::mostream*>& streams) {
    static std::ostringstream* const text = [&streams] {
        auto* t = new std::ostringstream;  // never destroyed: OpenMesh's streams outlive any static of ours
        for (OpenMesh::mostream* s : streams) {
            s->flush();
            for (std::ostream* std_stream : {&std::cout, &std::cerr, &std::clog}) s->disconnect(*std_stream);
            s->connect(*t);
            s->disable();
        }
        return t;
    }();
    return *text;
}

}  // namespace

CaptureOpenMeshLog::CaptureOpenMeshLog() : text_(capture_buffer(streams_)) {
    text_.str(std::string());
    text_.clear();
    for (OpenMesh::mostream* s : streams_) s->enable();
}

CaptureOpenMeshLog::~CaptureOpenMeshLog() {
    for (OpenMesh::mostream* s : streams_) {
        s->flush();
        s->disable();
    }
    text_.str(std::string());
}

std::string CaptureOpenMeshLog::first_line() {
    for (OpenMesh::mostream* s : streams_) s->flush();
    std::istringstream in(text_.str());
    std::string line;
    while (std::getline(in, line)) {
        const auto b = line.find_first_not_of(" \t\r");
        if (b != std::string::npos) return line.substr(b, 120);
    }
    return {};
}

std::mutex& CaptureOpenMeshLog::mutex() {
    static std::mutex m;
    return m;
}

}  // namespace tridex::compute
