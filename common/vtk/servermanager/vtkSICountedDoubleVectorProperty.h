// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkSICountedDoubleVectorProperty
 * @brief   A repeatable double property that also tells its VTK object how many numbers the user gave.
 *
 * ParaView pushes a `repeat_command` property row by row (`number_of_elements_per_command` numbers a call) and
 * silently drops a last, partial row; its `set_number_command` receives the number of whole rows. So a filter never
 * learns that `Terms = [9 numbers]` had two numbers too many. With this class as the property's server-side helper,
 *
 *     <DoubleVectorProperty name="Terms" command="AddTerm" clean_command="ClearTerms" repeat_command="1"
 *       number_of_elements_per_command="7" si_class="vtkSICountedDoubleVectorProperty"
 *       element_count_command="SetTermsElementCount" ...>
 *
 * the object gets the usual clean and row commands, then `SetTermsElementCount(n)` with the property's raw number
 * of elements, and can refuse a partial row with an error naming the property. The panel (a table with one column
 * per number) and state files are unchanged: the proxy side of the property is ParaView's own.
 *
 * On a fixed-size property (no repeat_command, number_of_elements="3": a point), a state file with another count
 * would make ParaView call the set method with the wrong arguments ("could not find requested method ... Aborting
 * execution"), which drops the rest of the proxy's state, its Input among it. With this helper the values are not
 * pushed: the object gets `element_count_command(n)` (and can refuse to run, naming the property), or without one
 * the helper reports an error naming the property; the rest of the state loads.
 */
#ifndef vtkSICountedDoubleVectorProperty_h
#define vtkSICountedDoubleVectorProperty_h

#include "PlantMorphServerManagerModule.h" // for export macro
#include "vtkSIDoubleVectorProperty.h"

#include <string>

class PLANTMORPHSERVERMANAGER_EXPORT vtkSICountedDoubleVectorProperty : public vtkSIDoubleVectorProperty
{
public:
  static vtkSICountedDoubleVectorProperty* New();
  vtkTypeMacro(vtkSICountedDoubleVectorProperty, vtkSIDoubleVectorProperty);
  void PrintSelf(ostream& os, vtkIndent indent) override;

protected:
  vtkSICountedDoubleVectorProperty();
  ~vtkSICountedDoubleVectorProperty() override;

  bool ReadXMLAttributes(vtkSIProxy* proxyhelper, vtkPVXMLElement* element) override;
  bool Push(vtkSMMessage* message, int offset) override;

private:
  vtkSICountedDoubleVectorProperty(const vtkSICountedDoubleVectorProperty&) = delete;
  void operator=(const vtkSICountedDoubleVectorProperty&) = delete;

  std::string ElementCountCommand;
  int FixedCount = -1; ///< number_of_elements of a property that is not repeated; -1 for a repeated one
};

#endif
