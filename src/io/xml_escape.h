#pragma once
// Text for an XML attribute or element (VTK's .pvd, XDMF): & < > " escaped. Names in these files
// come from scenes and paths, which may hold anything.
#include <string>

namespace nsf {

std::string xml_escape(const std::string& s);

}  // namespace nsf
