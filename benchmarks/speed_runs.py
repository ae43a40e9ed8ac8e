# SPDX-License-Identifier: GPL-3.0-or-later
"""What the speed benchmarks measure alike: a process's peak memory, an update's wall and CPU time, and a filter's
first and warm updates in the same process beside a VTK peer's.
"""
import time


def peak_mb():
    """This process's peak resident memory in MB (VmHWM: the process's own, where getrusage's ru_maxrss keeps a
    larger parent's across exec)."""
    with open("/proc/self/status") as status:
        return [int(line.split()[1]) for line in status if line.startswith("VmHWM")][0] / 1024.0


def timed(update):
    """Wall and CPU time (every thread) of `update()`, in seconds."""
    start, cpu = time.perf_counter(), time.process_time()
    update()
    return time.perf_counter() - start, time.process_time() - cpu


def first_and_warm(row, name, make, check, delete):
    """The first update of a new proxy `make()` in this process, then a warm one (a second proxy on the same input):
    `row[name_first_wall]`, `..._cpu`, the same for warm, and the peak memory after each (`peak_after_first_mb`,
    `peak_after_warm_mb`). `check(proxy, row)` reads the proxy's output into the row before `delete(proxy)`."""
    for run in ("first", "warm"):
        proxy = make()
        row[f"{name}_{run}_wall"], row[f"{name}_{run}_cpu"] = timed(proxy.UpdatePipeline)
        check(proxy, row)
        delete(proxy)
        row[f"peak_after_{run}_mb"] = peak_mb()


def vtk_first_and_warm(row, name, algorithm, cloud, neighbours=10):
    """A VTK point algorithm with `neighbours` neighbours (SetSampleSize) on `cloud`, twice: `row[name_first_wall]`,
    `..._cpu` and the same for warm."""
    for run in ("first", "warm"):
        peer = algorithm()
        peer.SetInputData(cloud)
        peer.SetSampleSize(neighbours)
        row[f"{name}_{run}_wall"], row[f"{name}_{run}_cpu"] = timed(peer.Update)
