// compute/mesh/openmesh_log.cpp - capturing OpenMesh's global log streams.
#include "compute/mesh/openmesh_log.hpp"

#include <iostream>

namespace tridex::compute {

CaptureOpenMeshLog::CaptureOpenMeshLog() : std_streams_{&std::cout, &std::cerr, &std::clog} {
    for (OpenMesh::mostream* s : streams_) {
        was_enabled_.push_back(s->is_enabled());
        for (std::ostream* std_stream : std_streams_) detached_.push_back(s->disconnect(*std_stream));
        s->connect(text_);
        s->enable();
    }
}

CaptureOpenMeshLog::~CaptureOpenMeshLog() {
    std::size_t k = 0;
    for (std::size_t i = 0; i < streams_.size(); ++i) {
        streams_[i]->flush();
        streams_[i]->disconnect(text_);
        for (std::ostream* std_stream : std_streams_)
            if (detached_[k++]) streams_[i]->connect(*std_stream);
        if (!was_enabled_[i]) streams_[i]->disable();
    }
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
