#!/usr/bin/env python3
"""ctest harness.translator_errors: pf2f90.py must reject .pf files outside the supported subset
with a ``file:line: error:`` message, and must translate a valid one.

Each case below is written to a temporary directory as ``<module>.pf``; standard library only.
"""

import argparse
import os
import subprocess
import sys
import tempfile

VALID = """module {name}
  use pfunit
  implicit none
contains
  @test
  subroutine test_a()
    @assertEqual(1, 1, message='a message with ! and , and &')
  end subroutine test_a
end module {name}
"""

#: (file basename, text, line the error must name, fragment of the message)
BAD_CASES = [
    ('test_wrong_name', VALID.format(name='test_other'), 1, 'must be named as the file'),
    ('test_args', VALID.replace('test_a()', 'test_a(x)'), 6, 'must take no arguments'),
    ('test_unknown', VALID.replace('@test', '@testcase'), 5, 'outside the .pf subset'),
    ('test_mpi_no_npes', VALID.replace('@test', '@mpitest'), 5, 'needs npes'),
    ('test_mpi_no_arg', VALID.replace('@test', '@mpitest(npes=[1,2])'), 6,
     'exactly one argument'),
    ('test_bad_assert', VALID.replace('@assertEqual', '@assertSame'), 7,
     'outside the supported subset'),
    ('test_operands', VALID.replace('@assertEqual(1, 1,', '@assertEqual(1,'), 7,
     'at least 2 operands'),
    # pFUnit 4.x translates a macro only on one line ending with its ")"
    ('test_continued', VALID.replace("1, 1, message=", "1, &\n      1, message="), 7,
     'continued with "&"'),
    ('test_trailing', VALID.replace(" and &')", " and &') ! why"), 7, 'comment after'),
    ('test_dangling', VALID.replace('  subroutine test_a()', '  integer :: k\n'
                                    '  subroutine test_a()'), 6, 'followed by a subroutine'),
    ('test_funit', VALID.replace('use pfunit', 'use funit'), 2, 'use pfunit'),
    ('test_no_tests', VALID.replace('  @test\n', ''), 1, 'no @test'),
]


def run(translator, directory, name, text, extra):
    path = os.path.join(directory, name + '.pf')
    with open(path, 'w', encoding='utf-8') as handle:
        handle.write(text)
    return path, subprocess.run([sys.executable, translator, path] + extra, capture_output=True,
                                text=True, check=False)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--translator', required=True, help='path of pf2f90.py')
    args = parser.parse_args()
    problems = []
    with tempfile.TemporaryDirectory() as directory:
        name = 'test_valid'
        path, result = run(args.translator, directory, name, VALID.format(name=name),
                           ['-o', os.path.join(directory, name + '.F90')])
        if result.returncode != 0:
            problems.append(f'valid file rejected: {result.stderr.strip()}')
        _, result = run(args.translator, directory, name, VALID.format(name=name), ['--info'])
        if result.stdout.strip() != 'serial=1 npes=':
            problems.append(f'--info of a serial file gave "{result.stdout.strip()}"')
        for base, text, line, fragment in BAD_CASES:
            if '{name}' in text:
                text = text.format(name=base)
            path, result = run(args.translator, directory, base, text,
                               ['-o', os.path.join(directory, base + '.F90')])
            expected = f'{path}:{line}: error:'
            if result.returncode == 0:
                problems.append(f'{base}: accepted')
            elif expected not in result.stderr or fragment not in result.stderr:
                problems.append(f'{base}: expected "{expected} ...{fragment}...", got '
                                f'"{result.stderr.strip()}"')
            else:
                print(f'ok   {base}: {result.stderr.strip()}')
    for problem in problems:
        print('FAIL', problem)
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
