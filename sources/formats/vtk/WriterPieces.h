// SPDX-License-Identifier: GPL-3.0-or-later
// What the two writers (vtkMtgWriter, vtkQsmWriter) share: under MPI each rank asks its input for its own piece (a
// writer has no output port to carry the piece request, so without this every rank would ask for the whole data
// and the first rank would gather as many copies as there are ranks); RunRequestData then gathers the pieces whole
// on the first rank, which writes the file.
#pragma once

#include "vtkInformation.h"
#include "vtkMultiProcessController.h"
#include "vtkStreamingDemandDrivenPipeline.h"

namespace plantmorph
{
/// Sets the input's update piece to this rank's, of as many pieces as ranks (nothing serially).
inline void RequestRankPiece(vtkInformation* input)
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  const int ranks = controller ? controller->GetNumberOfProcesses() : 1;
  if (ranks > 1 && input)
  {
    input->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), controller->GetLocalProcessId());
    input->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), ranks);
    input->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  }
}
} // namespace plantmorph
