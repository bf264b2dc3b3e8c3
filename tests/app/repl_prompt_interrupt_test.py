#!/usr/bin/env python3
"""Ctrl-C at the REPL's prompt drops the line being typed and the session goes on.

`granule repl` runs on a pseudo-terminal (readline's path). Typed but not entered,
`dropped = 1` is cut short by Ctrl-C; the next line finds `dropped` unset, a line
after that runs as usual, and Ctrl-D ends the session with status 0.

Usage: repl_prompt_interrupt_test.py GRANULE
"""
import os
import pty
import select
import sys
import time


def read_for(fd, seconds):
    out, end = b"", time.time() + seconds
    while time.time() < end:
        ready, _, _ = select.select([fd], [], [], 0.1)
        if ready:
            try:
                out += os.read(fd, 4096)
            except OSError:
                break
    return out.decode(errors="replace")


def main():
    granule = sys.argv[1]
    pid, fd = pty.fork()
    if pid == 0:
        os.environ["HOME"] = "/nonexistent"  # no history file read or written
        os.execv(granule, [granule, "repl", "-q"])
    seen = read_for(fd, 3)
    if "> " not in seen:
        print(f"FAILED: no prompt: {seen!r}")
        return 1
    os.write(fd, b"dropped = 1")
    read_for(fd, 0.5)
    os.write(fd, b"\x03")
    seen = read_for(fd, 1)
    done, status = os.waitpid(pid, os.WNOHANG)
    if done:
        print(f"FAILED: Ctrl-C at the prompt ended the REPL (status {status}): {seen!r}")
        return 1
    os.write(fd, b'print(dropped == nil and "line dropped" or "line kept")\r')
    seen = read_for(fd, 2)
    if "line dropped" not in seen:
        print(f"FAILED: the line typed before Ctrl-C ran or the REPL did not answer: {seen!r}")
        return 1
    os.write(fd, b"print(6 * 7)\r")
    seen = read_for(fd, 2)
    if "42" not in seen:
        print(f"FAILED: the session did not go on after Ctrl-C: {seen!r}")
        return 1
    os.write(fd, b"\x04")
    end = time.time() + 10
    while time.time() < end:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            if os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0:
                print("repl prompt interrupt ok")
                return 0
            print(f"FAILED: Ctrl-D ended the session with status {status}")
            return 1
        read_for(fd, 0.2)
    print("FAILED: Ctrl-D did not end the session")
    return 1


if __name__ == "__main__":
    sys.exit(main())
