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

/// Routes OpenMesh's log streams (omerr, omout, omlog) into a string for the lifetime of the object. The first
/// capture detaches them from the standard streams for good and connects them to one process-wide buffer (so no
/// capture allocates a stream target); between captures they are disabled and what OpenMesh says is dropped.
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
    std::vector<OpenMesh::mostream*> streams_{&::omerr(), &::omout(), &::omlog()};
    std::ostringstream& text_;  // the process-wide capture buffer
};

}  // namespace tridex::compute
