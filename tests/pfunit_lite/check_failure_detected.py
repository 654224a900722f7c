#!/usr/bin/env python3
"""ctest harness.failure_detected: failing assertions must make a pfunit-lite test run fail.

Runs the executable built from a ``selftest/harness_failing_*.pf`` file at every rank count named
in the file's ``expect-summary np=<n>:`` lines and checks, for each run:

* the exit status is non-zero;
* the line after each comment ``! expect-fail np=<n> shows: <text>`` is reported as
  ``<file>.pf:<line>: FAILED`` and ``<text>`` appears in the output (the marker sits on the line
  before the assertion: a macro's line holds nothing after its closing parenthesis);
* no text marked ``hidden: <text>`` appears (an assertion after a failure must not run);
* the summary line holds the expected ``<p> passed, <f> failed``.

Standard library only.
"""

import argparse
import os
import re
import subprocess
import sys


def expectations(pf_path):
    """Parse the markers of the .pf file."""
    summaries, fails, hidden = {}, {}, []
    with open(pf_path, encoding='utf-8') as handle:
        for lineno, line in enumerate(handle, start=1):
            match = re.search(r'expect-summary np=(\d+): (\d+ passed, \d+ failed)', line)
            if match:
                summaries[int(match.group(1))] = match.group(2)
            match = re.search(r'expect-fail np=(\d+) shows: (.*)$', line)
            if match:
                fails.setdefault(int(match.group(1)), []).append(
                    (lineno + 1, match.group(2).strip()))
            match = re.search(r'hidden: (.*)$', line)
            if match:
                hidden.append(match.group(1).strip())
    return summaries, fails, hidden


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--pf', required=True, help='the deliberately failing .pf file')
    parser.add_argument('--exe', required=True, help='its test executable')
    parser.add_argument('--mpiexec', default='mpiexec')
    parser.add_argument('--numproc-flag', default='-n')
    args = parser.parse_args()

    base = os.path.basename(args.pf)
    summaries, fails, hidden = expectations(args.pf)
    if not summaries or not fails:
        print(f'{args.pf}: no expect-summary / expect-fail markers found')
        return 1
    problems = []
    for nranks, summary in sorted(summaries.items()):
        command = [args.mpiexec, args.numproc_flag, str(nranks), args.exe]
        print('running:', ' '.join(command))
        try:
            result = subprocess.run(command, capture_output=True, text=True, timeout=240,
                                    check=False)
        except subprocess.TimeoutExpired:
            problems.append(f'np={nranks}: timed out')
            continue
        output = result.stdout + result.stderr
        print(output)
        if result.returncode == 0:
            problems.append(f'np={nranks}: exit status 0 although assertions failed')
        for lineno, text in fails.get(nranks, []):
            if f'{base}:{lineno}: FAILED' not in output:
                problems.append(f'np={nranks}: no failure reported for {base}:{lineno}')
            if text not in output:
                problems.append(f'np={nranks}: "{text}" missing from the report of line {lineno}')
        reported = set(int(n) for n in re.findall(re.escape(base) + r':(\d+): FAILED', output))
        unexpected = reported - {lineno for lineno, _ in fails.get(nranks, [])}
        if unexpected:
            problems.append(f'np={nranks}: unexpected failures at lines {sorted(unexpected)}')
        for text in hidden:
            if text in output:
                problems.append(f'np={nranks}: "{text}" reported: a test went on after a failure')
        if f'{summary} (' not in output:
            problems.append(f'np={nranks}: summary "{summary}" not found')
    for problem in problems:
        print('harness.failure_detected:', problem)
    print('harness.failure_detected:', 'FAILED' if problems else 'OK')
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
