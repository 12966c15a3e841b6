#!/usr/bin/env python3
"""Whether two written programs differ only where a point moved within its last digit.

    bench/close-output.py OLD_DIR NEW_DIR [TOLERANCE_MM]

Compares each pair of files of the same name under the two directories (what
bench/same-output.sh writes): the reports, messages and exit codes must be the same byte
for byte; a written program must have the same lines, word for word, but for coordinates that
differ by at most one unit in their last printed digit (or the axis' value before's) or,
for lengths, a tenth of the job's default tolerance (a point placed within a tenth of the tolerance of where it was can
round the other way; a word equal to the line before's may then be written or left out). Prints
each other difference and exits 1 if there is one; else one line of counts.
"""
import os
import re
import subprocess
import sys

NUMBER = re.compile(r"([A-Z])\s*([-+]?(?:\d+\.?\d*|\.\d+))")


def last_digit(text):
    """The value of one unit in the last printed digit of a number's text."""
    return 10.0 ** -(len(text.split(".")[1]) if "." in text else 0)


AXES = "XYZABCUVW"  # modal: a word left out keeps the last value
COORDINATES = AXES + "IJKR"


def coordinates(line):
    """The line with its coordinate words taken out, and those words by letter."""
    words = {}

    def take(m):
        if m.group(1) in COORDINATES:
            words[m.group(1)] = m.group(2)
            return ""
        return m.group(0)

    return NUMBER.sub(take, line).split(), words


TOLERANCE_MM = 0.001  # the job's default; the third argument sets another
LINEAR = "XYZUVWIJKR"


def allowed(letter, a, b, inch, before=None):
    """How far two printed values may be apart: one unit in their last digit or in that of
    the axis' value before (a take-up is written from the point it starts at, as rounded),
    or a tenth of the tolerance for a length (in the program's unit)."""
    unit = max(last_digit(a), last_digit(b), last_digit(before) if before else 0.0)
    if letter in LINEAR:
        unit = max(unit, TOLERANCE_MM / 10 / (25.4 if inch else 1.0))
    return unit


def close_lines(old, new, old_axes, new_axes, inch=False):
    """None where the lines match so, else why not; old_axes and new_axes follow the
    axes' values (a word repeated from the line before may be left out on one side only)."""
    old_rest, old_words = coordinates(old)
    new_rest, new_words = coordinates(new)
    if old_rest != new_rest:
        return "the words other than coordinates differ"
    for letter in set(old_words) | set(new_words):
        a = old_words.get(letter, old_axes.get(letter)) if letter in AXES else old_words.get(letter)
        b = new_words.get(letter, new_axes.get(letter)) if letter in AXES else new_words.get(letter)
        if a is None or b is None:
            return f"{letter} only on one side"
        before = old_axes.get(letter) if letter in AXES else None
        if abs(float(a) - float(b)) > allowed(letter, a, b, inch, before) * (1 + 1e-9):
            return f"{letter}{a} against {letter}{b}: further apart than allowed"
    return None


def follow(axes, line):
    for letter, value in coordinates(line)[1].items():
        if letter in AXES:
            axes[letter] = value


def align(old_path, new_path, old_count, new_count):
    """Pairs of line indices, in order, from GNU diff's edit script: lines of a hunk that
    changes as many lines as it has paired one by one, the others (lines added or left out)
    returned apart."""
    script = subprocess.run(["diff", old_path, new_path], capture_output=True, text=True).stdout
    pairs, only_old, only_new = [], [], []
    i = j = 0  # next unpaired line on each side
    for m in re.finditer(r"^(\d+)(?:,(\d+))?([acd])(\d+)(?:,(\d+))?$", script, re.M):
        a1, a2, op, b1, b2 = int(m.group(1)), int(m.group(2) or m.group(1)), m.group(3), int(m.group(4)), int(
            m.group(5) or m.group(4))
        first_old, last_old = (a1 + 1, a1) if op == "a" else (a1, a2)  # 1-based, inclusive
        first_new, last_new = (b1 + 1, b1) if op == "d" else (b1, b2)
        while i < first_old - 1:
            pairs.append((i, j))
            i, j = i + 1, j + 1
        if op == "c" and last_old - first_old == last_new - first_new:
            pairs += zip(range(first_old - 1, last_old), range(first_new - 1, last_new))
        else:
            only_old += range(first_old - 1, last_old)
            only_new += range(first_new - 1, last_new)
        i, j = last_old, last_new
    while i < old_count:
        pairs.append((i, j))
        i, j = i + 1, j + 1
    return pairs, only_old, only_new


def main():
    global TOLERANCE_MM
    old_dir, new_dir = sys.argv[1], sys.argv[2]
    if len(sys.argv) > 3:
        TOLERANCE_MM = float(sys.argv[3])
    files = numbers = problems = 0
    for name in sorted(os.listdir(old_dir)):
        with open(os.path.join(old_dir, name), "rb") as f:
            old = f.read()
        with open(os.path.join(new_dir, name), "rb") as f:
            new = f.read()
        if old == new:
            continue
        files += 1
        if not name.endswith(".ngc"):
            print(f"{name}: differs (not a written program)")
            problems += 1
            continue
        old_lines, new_lines = old.decode().splitlines(), new.decode().splitlines()
        if len(old_lines) != len(new_lines):
            # Lines added or left out (a take-up, a split): aligned on the words but the
            # coordinates, shown, and the rest compared as below.
            print(f"{name}: {len(old_lines)} lines against {len(new_lines)}")
            problems += 1
            pairs, only_old, only_new = align(os.path.join(old_dir, name), os.path.join(new_dir, name),
                                              len(old_lines), len(new_lines))
            for k in only_old:
                print(f"  {name}:{k + 1}: only before: {old_lines[k]}")
            for k in only_new:
                print(f"  {name}:{k + 1}: only after: {new_lines[k]}")
        else:
            pairs = [(k, k) for k in range(len(old_lines))]
        old_axes, new_axes = {}, {}
        inch = False
        last_old = last_new = -1
        for i, j in pairs:
            # the axes' values where lines were added or left out
            for k in range(last_old + 1, i):
                follow(old_axes, old_lines[k])
            for k in range(last_new + 1, j):
                follow(new_axes, new_lines[k])
            a, b = old_lines[i], new_lines[j]
            if re.search(r"G0*2[01](?!\d)", a):
                inch = re.search(r"G0*20(?!\d)", a) is not None
            if a != b:
                numbers += 1
                why = close_lines(a, b, old_axes, new_axes, inch)
                if why:
                    print(f"{name}:{j + 1}: {why}\n  {a}\n  {b}")
                    problems += 1
            follow(old_axes, a)
            follow(new_axes, b)
            last_old, last_new = i, j
    if problems:
        return 1
    print(f"close-output: {files} files differ, in {numbers} lines, each within a last digit or a tenth of the tolerance")
    return 0


if __name__ == "__main__":
    sys.exit(main())
