// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkSICountedIntVectorProperty
 * @brief   An integer property that tells its VTK object how many numbers the user gave, and survives a state file
 *          with another count.
 *
 * The integer twin of vtkSICountedDoubleVectorProperty (read it): on a fixed-size property (a choice, a flag, a
 * count, a resolution pair) a state file with another number of values would make ParaView call the set method with
 * the wrong arguments ("could not find requested method ... Aborting execution"), which drops the rest of the proxy's
 * state, its Input among it. With this helper the values are not pushed and an error names the property (or the
 * object hears `element_count_command(n)`); the rest of the state loads.
 */
#ifndef vtkSICountedIntVectorProperty_h
#define vtkSICountedIntVectorProperty_h

#include "PlantMorphServerManagerModule.h" // for export macro
#include "vtkSIIntVectorProperty.h"

#include <string>

class PLANTMORPHSERVERMANAGER_EXPORT vtkSICountedIntVectorProperty : public vtkSIIntVectorProperty
{
public:
  static vtkSICountedIntVectorProperty* New();
  vtkTypeMacro(vtkSICountedIntVectorProperty, vtkSIIntVectorProperty);
  void PrintSelf(ostream& os, vtkIndent indent) override;

protected:
  vtkSICountedIntVectorProperty();
  ~vtkSICountedIntVectorProperty() override;

  bool ReadXMLAttributes(vtkSIProxy* proxyhelper, vtkPVXMLElement* element) override;
  bool Push(vtkSMMessage* message, int offset) override;

private:
  vtkSICountedIntVectorProperty(const vtkSICountedIntVectorProperty&) = delete;
  void operator=(const vtkSICountedIntVectorProperty&) = delete;

  std::string ElementCountCommand;
  int FixedCount = -1; ///< number_of_elements of a property that is not repeated; -1 for a repeated one
};

#endif
