#pragma once
// The built-in constitutive models of App. F, by scene "type" key.
#include <map>
#include <string>

#include "mpm/materials/material.h"

namespace nsf {

std::map<std::string, MaterialFactory> builtin_materials();

}  // namespace nsf
