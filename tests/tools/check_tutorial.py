#!/usr/bin/python3
"""Every ```lua block of docs/tutorial.md must appear verbatim in the tutorial scene.

usage: /usr/bin/python3 tests/tools/check_tutorial.py docs/tutorial.md scenarios/tutorial_drum.lua
"""
import re
import sys

doc, scene = (open(p).read() for p in sys.argv[1:3])
blocks = re.findall(r"```lua\n(.*?)```", doc, re.S)
if len(blocks) < 5:
    sys.exit(f"only {len(blocks)} lua blocks in {sys.argv[1]}")
for block in blocks:
    if block not in scene:
        sys.exit(f"this block of {sys.argv[1]} is not in {sys.argv[2]}:\n{block}")
print(f"{len(blocks)} blocks of the tutorial match the scene")
