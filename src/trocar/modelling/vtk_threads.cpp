// Compiled as C++17: vtkSMPTools.h does not compile with g++ 12 in C++20.
#include <vtkSMPTools.h>

#include "trocar/modelling/vtk_threads.h"

namespace trocar {

void use_one_vtk_thread() {
  static const bool done = [] {
    vtkSMPTools::SetBackend("Sequential");
    vtkSMPTools::Initialize(1);
    return true;
  }();
  (void)done;
}

}  // namespace trocar
