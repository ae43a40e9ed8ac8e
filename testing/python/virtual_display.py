# SPDX-License-Identifier: GPL-3.0-or-later
"""A private Xvfb server for one command, started without races (plain python3).

    python3 virtual_display.py [--screen 1920x1080x24] -- COMMAND ...   (runs COMMAND with DISPLAY set to the server)

`xvfb-run -a` picks a display number by looking for a free lock file and then starts Xvfb on it. Two tests that start
at the same moment (ctest -j2) can pick the same number: one server fails to start, and its command then connects to
the other test's server with the wrong cookie ("bad X server connection") or loses it when that test ends. Here
Xvfb chooses the number itself and reports it (-displayfd), which the X server does atomically, so every command
gets a server of its own. The server listens on its local socket only and is stopped when the command ends."""
import argparse
import os
import select
import subprocess
import sys


class VirtualDisplay:
    """Context manager: starts Xvfb with the given screen ("WIDTHxHEIGHTxDEPTH"); `display` is its ":N"."""

    def __init__(self, screen="1920x1080x24", timeout=30.0):
        self.screen = screen
        self.timeout = timeout
        self.process = None
        self.display = None

    def __enter__(self):
        self.process = subprocess.Popen(["Xvfb", "-displayfd", "1", "-screen", "0", self.screen, "-nolisten", "tcp"],
                                        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, stdin=subprocess.DEVNULL)
        ready, _, _ = select.select([self.process.stdout], [], [], self.timeout)
        number = self.process.stdout.readline().decode().strip() if ready else ""
        if not number.isdigit():
            self.__exit__(None, None, None)
            raise RuntimeError("Xvfb did not report a display within %.0f s" % self.timeout)
        self.display = ":" + number
        return self

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
