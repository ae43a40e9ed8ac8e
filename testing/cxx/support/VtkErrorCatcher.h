// SPDX-License-Identifier: GPL-3.0-or-later
// Collects the text of a VTK object's error events, so a test can assert the message a bad property produces.
//
//   vtkNew<ErrorCatcher> catcher;
//   filter->AddObserver(vtkCommand::ErrorEvent, catcher);
#pragma once

#include "vtkCommand.h"

#include <string>

namespace plantmorph::testing
{

class ErrorCatcher : public vtkCommand
{
public:
  static ErrorCatcher* New() { return new ErrorCatcher; }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    if (data)
      this->Messages += static_cast<const char*>(data);
  }
  std::string Messages;
};

} // namespace plantmorph::testing
