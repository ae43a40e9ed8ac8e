// SPDX-License-Identifier: GPL-3.0-or-later
// The VTK layer (common/vtk/PlantMorphLayer.h): RunRequestData leaves every output port empty and says the error
// once whatever the body throws, out of memory included; SMPFor runs on threads when vtkSMPTools is left on its
// Sequential default, and on one when one thread is asked for; FieldRecord prefixes its names; PresetOverrides lists
// only the changed properties; KeepFreedMemory makes a freed block's memory serve the next one without new page
// faults.
#include "PlantMorphAlgorithmHooks.h"
#include "PlantMorphLayer.h"
#include "VtkErrorCatcher.h"

#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataAlgorithm.h"
#include "vtkSMPTools.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <memory>
#include <mutex>
#include <new>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#if defined(__GLIBC__)
#include <sys/resource.h>
#endif

namespace
{
using plantmorph::testing::ErrorCatcher;

/// A source of two ports whose body fills both, then does what the test asks (nothing, fail, throw).
class LayerProbe : public vtkPolyDataAlgorithm
{
public:
  static LayerProbe* New();
  vtkTypeMacro(LayerProbe, vtkPolyDataAlgorithm);
  std::function<void(plantmorph::Run&)> Then = [](plantmorph::Run&) {};

protected:
  LayerProbe()
  {
    this->SetNumberOfInputPorts(0);
    this->SetNumberOfOutputPorts(2);
  }
  int RequestData(vtkInformation* request, vtkInformationVector** in, vtkInformationVector* out) override
  {
    return plantmorph::RunRequestData(this, plantmorph::MPIPolicy::WholeOnFirstRank, "the probe's points", request, in,
      out, [this](plantmorph::Run& run) {
        for (int port = 0; port < 2; ++port)
        {
          vtkNew<vtkPoints> points;
          points->InsertNextPoint(0.0, 0.0, 0.0);
          run.Output<vtkPolyData>(port)->SetPoints(points);
        }
        plantmorph::FieldRecord record;
        record.Add("Probe", 1.0);
        run.WriteToEveryOutput(record);
        this->Then(run);
      });
  }
};
vtkStandardNewMacro(LayerProbe);

/// Runs the probe with `then`; the error text it reported.
std::string RunProbe(LayerProbe* probe, std::function<void(plantmorph::Run&)> then)
{
  vtkNew<ErrorCatcher> catcher;
  probe->AddObserver(vtkCommand::ErrorEvent, catcher);
  probe->Then = std::move(then);
  probe->Modified();
  probe->Update();
  probe->RemoveAllObservers();
  return catcher->Messages;
}

bool Empty(LayerProbe* probe)
{
  return probe->GetOutput(0)->GetNumberOfPoints() == 0 && probe->GetOutput(1)->GetNumberOfPoints() == 0 &&
    probe->GetOutput(0)->GetFieldData()->GetNumberOfArrays() == 0;
}
} // namespace

TEST(VtkLayer, ASuccessfulRunKeepsEveryOutputAndItsFieldData)
{
  vtkNew<LayerProbe> probe;
  EXPECT_EQ(RunProbe(probe, [](plantmorph::Run&) {}), "");
  EXPECT_EQ(probe->GetOutput(0)->GetNumberOfPoints(), 1);
  EXPECT_EQ(probe->GetOutput(1)->GetNumberOfPoints(), 1);
  EXPECT_NE(probe->GetOutput(1)->GetFieldData()->GetArray("PlantMorph.Probe"), nullptr);
}

TEST(VtkLayer, AFailureSaysItsMessageOnceAndEmptiesEveryPort)
{
  vtkNew<LayerProbe> probe;
  const std::string said = RunProbe(probe, [](plantmorph::Run& run) { run.Fail("Width = -1 is outside the range"); });
  EXPECT_NE(said.find("Width = -1 is outside the range"), std::string::npos) << said;
  EXPECT_EQ(said.find("Width", said.find("Width") + 1), std::string::npos) << "said once: " << said;
  EXPECT_TRUE(Empty(probe));
}

TEST(VtkLayer, OutOfMemoryNamesWhatWasBeingBuiltAndEmptiesEveryPort)
{
  vtkNew<LayerProbe> probe;
  const std::string said = RunProbe(probe, [](plantmorph::Run& run) {
    run.Building("the probe's mesh");
    throw std::bad_alloc();
  });
  EXPECT_NE(said.find("ran out of memory building the probe's mesh"), std::string::npos) << said;
  EXPECT_TRUE(Empty(probe));
  // The next run is whole again.
  EXPECT_EQ(RunProbe(probe, [](plantmorph::Run&) {}), "");
  EXPECT_EQ(probe->GetOutput(1)->GetNumberOfPoints(), 1);
}

TEST(VtkLayer, AnyOtherExceptionAndAStopAlsoEmptyEveryPort)
{
  vtkNew<LayerProbe> probe;
  const std::string said = RunProbe(probe, [](plantmorph::Run&) { throw std::runtime_error("index out of range"); });
  EXPECT_NE(said.find("failed building the probe's points: index out of range"), std::string::npos) << said;
  EXPECT_TRUE(Empty(probe));
  EXPECT_EQ(RunProbe(probe, [](plantmorph::Run& run) { run.Stop(); }), "") << "a stop says nothing";
  EXPECT_TRUE(Empty(probe));
}

TEST(VtkLayer, RunThreadedRestoresTheBackendAfterAThrow)
{
  const std::string before = vtkSMPTools::GetBackend() ? vtkSMPTools::GetBackend() : "";
  EXPECT_THROW(plantmorph::RunThreaded(2, [] { plantmorph::Fail("stop"); }), plantmorph::RunFailure);
  EXPECT_EQ(std::string(vtkSMPTools::GetBackend() ? vtkSMPTools::GetBackend() : ""), before);
}

// An exception thrown on a vtkSMPTools worker thread used to end the process (std::terminate: a VirtualScanner
// out of memory aborted ParaView). SMPFor hands it to the calling thread, where RunRequestData reports it.
TEST(VtkLayer, AnExceptionOnAWorkerThreadReachesTheBoundary)
{
  vtkNew<LayerProbe> probe;
  const std::string said = RunProbe(probe, [](plantmorph::Run& run) {
    run.Building("the probe's cloud");
    run.Threaded(4, [] {
      plantmorph::SMPFor(1)(64, [](std::size_t begin, std::size_t) {
        if (begin >= 32) // not the calling thread's first chunk alone
          throw std::bad_alloc();
      });
    });
  });
  EXPECT_NE(said.find("ran out of memory building the probe's cloud"), std::string::npos) << said;
  EXPECT_TRUE(Empty(probe));
  // Every chunk once when nothing throws.
  std::vector<int> seen(1000, 0);
  plantmorph::RunThreaded(4, [&] {
    plantmorph::SMPFor(7)(seen.size(), [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i)
        ++seen[i];
    });
  });
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), 1000);
}

/// The threads that ran SMPFor(1)'s chunks of a 64-chunk loop (each chunk long enough for a second thread to start).
std::set<std::thread::id> ThreadsOfALoop()
{
  std::mutex lock;
  std::set<std::thread::id> threads;
  plantmorph::SMPFor(1)(64, [&](std::size_t, std::size_t) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    std::lock_guard<std::mutex> guard(lock);
    threads.insert(std::this_thread::get_id());
  });
  return threads;
}

// pvpython, pvbatch and the GUI start vtkSMPTools on its Sequential backend: our loops run on threads all the same,
// and leave the process-wide backend as they found it; one thread asked for (a filter's NumberOfThreads 1) is one.
TEST(VtkLayer, SMPForIsThreadedOnTheDefaultSequentialBackend)
{
  if (std::getenv("VTK_SMP_BACKEND_IN_USE") || std::getenv("VTK_SMP_MAX_THREADS"))
    GTEST_SKIP() << "the environment sets the backend or the thread count: SMPFor keeps them";
  if (std::thread::hardware_concurrency() < 2)
    GTEST_SKIP() << "one core";
  const std::string before = vtkSMPTools::GetBackend();
  ASSERT_TRUE(vtkSMPTools::SetBackend("Sequential"));
  EXPECT_GE(ThreadsOfALoop().size(), 2u);
  EXPECT_EQ(std::string(vtkSMPTools::GetBackend()), "Sequential");
  std::set<std::thread::id> one;
  plantmorph::RunThreaded(1, [&] { one = ThreadsOfALoop(); });
  EXPECT_EQ(one, std::set<std::thread::id>{ std::this_thread::get_id() });
  EXPECT_EQ(std::string(vtkSMPTools::GetBackend()), "Sequential");
  vtkSMPTools::SetBackend(before.c_str());
}

#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
/// Page faults of this process so far (minor: fresh memory touched the first time).
long MinorFaults()
{
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}

/// Page faults of filling a fresh `bytes`-byte array, freed before returning.
long FaultsOfAnArray(std::size_t bytes)
{
  const long before = MinorFaults();
  {
    std::vector<unsigned char> block(bytes, 1);
    EXPECT_EQ(block[bytes / 2], 1);
  }
  return MinorFaults() - before;
}

/// The first environment variable set that makes KeepFreedMemory leave malloc alone, else null. Written out here, not
/// asked of the function under test, so that a broken function cannot skip its own tests.
const char* UserMallocSetting()
{
  for (const char* name :
    { "MALLOC_MMAP_THRESHOLD_", "MALLOC_TRIM_THRESHOLD_", "GLIBC_TUNABLES", "PLANTMORPH_MALLOC_DEFAULTS" })
    if (std::getenv(name))
      return name;
  return nullptr;
}

TEST(VtkLayer, KeepFreedMemoryReusesAFreedArrayWithoutPageFaults)
{
  if (const char* name = UserMallocSetting())
    GTEST_SKIP() << name << " is set: malloc is left as the user tuned it";
  ASSERT_TRUE(plantmorph::KeepFreedMemory());
  EXPECT_TRUE(plantmorph::KeepFreedMemory()) << "once set, it stays set";
  // 24 MB: the coordinates of 10^6 points. glibc's default maps such a block fresh and unmaps it when it is freed;
  // its own threshold then rises only to the size of that block, so a larger one is mapped fresh again.
  const std::size_t bytes = 24u << 20;
  const long pages = static_cast<long>(bytes / 4096);
  FaultsOfAnArray(bytes); // the heap grows once (its first touch faults)
  const long again = FaultsOfAnArray(bytes);
  EXPECT_LT(again, pages / 10) << "the freed block's memory is used again, not taken fresh from the system";
  const long larger = FaultsOfAnArray(bytes + (4u << 20));
  EXPECT_LT(larger, pages / 2) << "a larger block grows the heap by the difference only";
}

/// The kernel's transparent huge page mode ("always", "madvise" or "never"), empty where there is none.
std::string HugePageMode()
{
  std::ifstream file("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string line;
  std::getline(file, line);
  const auto open = line.find('['), close = line.find(']');
  return open == std::string::npos || close == std::string::npos ? "" : line.substr(open + 1, close - open - 1);
}

// The first touch of fresh arrays: with the heap on huge pages a 24 MB array that was never allocated before faults
// once per 2 MiB, not once per 4 KiB (6,144 faults on glibc's defaults).
TEST(VtkLayer, KeepFreedMemoryPutsFreshArraysOnHugePages)
{
  if (const char* name = UserMallocSetting())
    GTEST_SKIP() << name << " is set: malloc is left as the user tuned it";
  const std::string mode = HugePageMode();
  if (mode != "always" && mode != "madvise")
    GTEST_SKIP() << "no transparent huge pages on this kernel (mode '" << mode << "')";
  ASSERT_TRUE(plantmorph::KeepFreedMemory());
  const std::size_t bytes = 24u << 20;
  const long pages = static_cast<long>(bytes / 4096);
  std::vector<std::unique_ptr<std::vector<unsigned char>>> held; // all alive: each is fresh memory
  const long before = MinorFaults();
  for (int k = 0; k < 4; ++k)
    held.push_back(std::make_unique<std::vector<unsigned char>>(bytes, 1));
  const long faults = MinorFaults() - before;
  EXPECT_LT(faults, 4 * pages / 8) << "four fresh 24 MB arrays: most of their memory on 2 MiB pages";
}
#endif

TEST(VtkLayer, FieldRecordPrefixesNamesOnce)
{
  plantmorph::FieldRecord record;
  record.Add("Length", 2.5);
  record.Add("PlantMorph.Model", "BSpline");
  record.AddTuple("Curvature", { "Mu", "Lambda" }, { 1.0, 2.0 });
  EXPECT_NE(record.Data()->GetArray("PlantMorph.Length"), nullptr);
  EXPECT_NE(record.Data()->GetAbstractArray("PlantMorph.Model"), nullptr);
  EXPECT_EQ(record.Data()->GetAbstractArray("PlantMorph.PlantMorph.Model"), nullptr);
  EXPECT_EQ(record.Text(), "Length = 2.5\nModel = BSpline\nCurvatureMu = 1\nCurvatureLambda = 2\n");
}

TEST(VtkLayer, PresetOverridesListsOnlyTheChangedProperties)
{
  plantmorph::PresetOverrides overrides("SpaceCurvePreset");
  overrides.Check("CurvatureMu", 2.0, 2.0);
  EXPECT_EQ(overrides.Message(), "") << "nothing changed: no warning";
  overrides.Check("Lobes", 3, 1);
  overrides.Check("Terms", std::vector<double>{ 1.0 }, std::vector<double>{});
  EXPECT_EQ(overrides.Message(),
    "these properties are changed from their defaults but not used, because SpaceCurvePreset is a named preset that "
    "sets them itself: Lobes, Terms. Set SpaceCurvePreset to Custom (0) to use them.");
}
