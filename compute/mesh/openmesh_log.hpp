// compute/mesh/openmesh_log.hpp - keeping OpenMesh's log lines ("[STLWriter] : write binary file", parse errors)
// off the terminal: mesh reading and writing capture them, and use the first one in their error messages.
#pragma once

#include <OpenMesh/Core/System/omstream.hh>

#include <mutex>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

namespace tridex::compute {

/// Routes OpenMesh's log streams (omerr, omout, omlog) into a string for the lifetime of the object:
/// detaches the standard streams they were connected to and re-attaches exactly those afterwards.
/// The streams are global, so callers hold `mutex()`.
class CaptureOpenMeshLog {
public:
    CaptureOpenMeshLog();
    ~CaptureOpenMeshLog();
    CaptureOpenMeshLog(const CaptureOpenMeshLog&) = delete;
    CaptureOpenMeshLog& operator=(const CaptureOpenMeshLog&) = delete;

    /// First non-blank line OpenMesh wrote, trimmed to 120 characters (empty if none).
    std::string first_line();
    /// Serialises every use of OpenMesh's global streams by tridex (reading and writing meshes).
    static std::mutex& mutex();

private:
    std::ostringstream text_;
    std::vector<OpenMesh::mostream*> streams_{&::omerr(), &::omout(), &::omlog()};
    std::vector<std::ostream*> std_streams_;
    std::vector<bool> was_enabled_;
    std::vector<bool> detached_;  // per (stream, std stream) pair
};

}  // namespace tridex::compute
