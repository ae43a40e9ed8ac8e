# SPDX-License-Identifier: GPL-3.0-or-later
"""A private Xvfb server for one command, started without races (plain python3).

    python3 virtual_display.py [--screen 1920x1080x24] -- COMMAND ...   (runs COMMAND with DISPLAY set to the server)

`xvfb-run -a` picks a display number by looking for a free lock file and then starts Xvfb on it. Two tests that start
at the same moment (ctest -j2) can pick the same number: one server fails to start, and its command then connects to
the other test's server with the wrong cookie ("bad X server connection") or loses it when that test ends. Here
each server is started on a display of its own choosing: Xvfb takes the display's lock file atomically, a server
that finds the number taken exits and the next number is tried, and it reports the number only once it accepts
connections (its local socket answers). The numbers start above 200, spread by process id, away from the displays
desktops and xvfb-run use. The server listens on its local socket only and is stopped when the command ends.

Even so, on these machines pvbatch's first connection to a fresh Xvfb now and then fails ("bad X server
connection", about one run in four under load, whichever way the server is started, xvfb-run included): the
callers run such a command again on a new server (run_example.py, gui_playback.py)."""
import argparse
import os
import socket
import subprocess
import sys
import time


class VirtualDisplay:
    """Context manager: starts Xvfb with the given screen ("WIDTHxHEIGHTxDEPTH"); `display` is its ":N"."""

    def __init__(self, screen="1920x1080x24", timeout=30.0):
        self.screen = screen
        self.timeout = timeout
        self.process = None
        self.display = None

    def __enter__(self):
        first = 200 + (os.getpid() % 400) * 4
        for number in range(first, first + 200):
            self.process = subprocess.Popen(["Xvfb", ":%d" % number, "-screen", "0", self.screen, "-nolisten", "tcp"],
                                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                            stdin=subprocess.DEVNULL)
            if self._ready(number):
                self.display = ":%d" % number
                return self
            self.__exit__(None, None, None)  # the number is taken (the server exited) or the server hangs
        raise RuntimeError("Xvfb found no free display in %d..%d" % (first, first + 199))

    def _ready(self, number):
        """Waits until the server accepts a connection on its local socket; False if it exits or times out."""
        path = "/tmp/.X11-unix/X%d" % number
        deadline = time.monotonic() + self.timeout
        while time.monotonic() < deadline:
            if self.process.poll() is not None:
                return False
            probe = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
            try:
                probe.connect(path)
                return True
            except OSError:
                time.sleep(0.05)
            finally:
                probe.close()
        return False

    def environment(self, base=None):
        """`base` (default os.environ) with DISPLAY set to this server."""
        return dict(os.environ if base is None else base, DISPLAY=self.display)

    def __exit__(self, *exception):
        if self.process is not None and self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        return False


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--screen", default="1920x1080x24")
    parser.add_argument("command", nargs=argparse.REMAINDER)
    arguments = parser.parse_args()
    command = arguments.command[1:] if arguments.command[:1] == ["--"] else arguments.command
    if not command:
        parser.error("no command given")
    with VirtualDisplay(arguments.screen) as server:
        return subprocess.call(command, env=server.environment())


if __name__ == "__main__":
    sys.exit(main())
