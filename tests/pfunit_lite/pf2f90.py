#!/usr/bin/env python3
"""Translate one pFUnit ``.pf`` test file into a Fortran source for the pfunit-lite runner.

MPMICE carries this small stand-in for pFUnit's ``funitproc`` so that the unit tests run where no
pFUnit installation exists (CI, laptops).  It understands the subset of pFUnit 4.x syntax fixed by
the design note (section 8) and documented in ``docs/testing.md``:

* one ``module`` per file, named exactly as the file's basename;
* ``@test`` on a module subroutine without arguments (serial test);
* ``@mpitest(npes=[...])`` or ``@test(npes=[...])`` on a subroutine with one argument,
  ``class(MpiTestMethod), intent(inout) :: this`` (MPI test);
* ``@before`` / ``@after`` on a subroutine with no argument or with the test object;
* ``@assert<Name>(...)`` macros at the start of a statement, each on one line that ends with its
  closing parenthesis: no ``&`` continuation and no trailing comment, which pFUnit 4.x's
  preprocessor leaves untranslated (the compiler then fails on the ``@``); both are rejected
  here with ``file:line: error:`` so that a file accepted here builds with a real pFUnit.

The output (one ``.F90`` file) holds the test module with the annotations commented out and the
macros expanded into calls of the ``pfunit`` support module, followed by a driver program that
runs every test (see ``pfunit_core.f90``).  ``#line`` directives map compiler messages back to the
``.pf`` file.

Usage::

    pf2f90.py tests/unit/test_foo.pf -o build/tests/unit/test_foo.F90
    pf2f90.py --info tests/unit/test_foo.pf      # prints "serial=<0|1> npes=<n1,n2,...>"
"""

import argparse
import os
import re
import sys

#: Assertion macros and the least number of positional operands each needs.
ASSERTIONS = {
    'equal': 2,
    'relativelyequal': 2,
    'true': 1,
    'false': 1,
    'lessthan': 2,
    'lessthanorequal': 2,
    'greaterthan': 2,
    'greaterthanorequal': 2,
    'isnan': 1,
    'isfinite': 1,
}

#: Fortran names of the assertion procedures (pFUnit's spelling).
ASSERTION_NAMES = {
    'equal': 'assertEqual',
    'relativelyequal': 'assertRelativelyEqual',
    'true': 'assertTrue',
    'false': 'assertFalse',
    'lessthan': 'assertLessThan',
    'lessthanorequal': 'assertLessThanOrEqual',
    'greaterthan': 'assertGreaterThan',
    'greaterthanorequal': 'assertGreaterThanOrEqual',
    'isnan': 'assertIsNan',
    'isfinite': 'assertIsFinite',
}

KEYWORD_ARGS = ('tolerance', 'message')

RE_ANNOTATION = re.compile(r'^\s*@(\w+)\s*(\((.*)\))?\s*$', re.IGNORECASE)
RE_ASSERT_START = re.compile(r'^(\s*)@assert(\w+)\s*\(', re.IGNORECASE)
RE_SUBROUTINE = re.compile(
    r'^\s*(?:(?:pure|impure|recursive|elemental|module)\s+)*subroutine\s+(\w+)\s*(\(([^)]*)\))?',
    re.IGNORECASE)
RE_MODULE = re.compile(r'^\s*module\s+(\w+)\s*(!.*)?$', re.IGNORECASE)
RE_USE_FUNIT = re.compile(r'^\s*use\s*(,\s*\w+\s*)?(::)?\s*funit\b', re.IGNORECASE)
RE_NPES = re.compile(r'npes\s*=\s*\[([0-9,\s]+)\]', re.IGNORECASE)


class PfError(Exception):
    """A problem in the .pf file, reported as file:line: message."""

    def __init__(self, path, line, message):
        super().__init__(f'{path}:{line}: error: {message}')


def strip_comment(text, quote=None):
    """Split a free-form source line into (code, quote state at the end of the code).

    ``quote`` is the string delimiter open at the start of the line (for continued strings).
    A ``!`` outside a string starts a comment, which is dropped.
    """
    code = []
    for ch in text:
        if quote:
            code.append(ch)
            if ch == quote:
                quote = None
        elif ch in ('"', "'"):
            quote = ch
            code.append(ch)
        elif ch == '!':
            break
        else:
            code.append(ch)
    return ''.join(code), quote


def split_args(text):
    """Split an argument list at the commas that are outside parentheses, brackets and strings."""
    args, depth, quote, current = [], 0, None, []
    for ch in text:
        if quote:
            current.append(ch)
            if ch == quote:
                quote = None
            continue
        if ch in ('"', "'"):
            quote = ch
        elif ch in '([':
            depth += 1
        elif ch in ')]':
            depth -= 1
        elif ch == ',' and depth == 0:
            args.append(''.join(current).strip())
            current = []
            continue
        current.append(ch)
    tail = ''.join(current).strip()
    if tail or args:
        args.append(tail)
    return args


def matching_paren(text, start):
    """Index of the parenthesis closing the one at ``text[start]``, or -1."""
    depth, quote = 0, None
    for i in range(start, len(text)):
        ch = text[i]
        if quote:
            if ch == quote:
                quote = None
            continue
        if ch in ('"', "'"):
            quote = ch
        elif ch == '(':
            depth += 1
        elif ch == ')':
            depth -= 1
            if depth == 0:
                return i
    return -1


def fortran_string(text):
    """A Fortran character literal holding ``text``."""
    return "'" + text.replace("'", "''") + "'"


class Procedure:
    """An annotated module subroutine."""

    def __init__(self, kind, npes, line):
        self.kind = kind          # 'test', 'mpitest', 'before' or 'after'
        self.npes = npes          # list of rank counts for MPI tests
        self.line = line          # line of the annotation
        self.name = None
        self.nargs = 0


class Translator:
    """Translate one .pf file."""

    def __init__(self, path):
        self.path = path
        self.base = os.path.basename(path)
        self.expected_module = os.path.splitext(self.base)[0]
        with open(path, encoding='utf-8') as handle:
            self.lines = handle.read().splitlines()
        self.module = None
        self.procedures = []
        self.pending = None

    def error(self, line, message):
        raise PfError(self.path, line, message)

    # ------------------------------------------------------------------ parsing helpers
    def annotation(self, lineno, match):
        """Record an @test/@mpitest/@before/@after annotation."""
        name = match.group(1).lower()
        options = match.group(3) or ''
        if self.pending is not None:
            self.error(lineno, f'annotation @{name} follows @{self.pending.kind} '
                       f'(line {self.pending.line}) before any subroutine')
        if name in ('test', 'mpitest'):
            npes_match = RE_NPES.search(options)
            rest = RE_NPES.sub('', options).strip(' ,')
            if rest:
                self.error(lineno, f'unsupported @{name} option "{rest}" (the lite runner '
                           'knows npes=[...] only)')
            if npes_match:
                npes = sorted({int(n) for n in npes_match.group(1).split(',') if n.strip()})
                if not npes or min(npes) < 1:
                    self.error(lineno, 'npes must list positive rank counts')
                self.pending = Procedure('mpitest', npes, lineno)
            elif name == 'mpitest':
                self.error(lineno, '@mpitest needs npes=[...]')
            else:
                self.pending = Procedure('test', [], lineno)
        elif name in ('before', 'after'):
            if options.strip():
                self.error(lineno, f'@{name} takes no options')
            self.pending = Procedure(name, [], lineno)
        else:
            self.error(lineno, f'@{name} is outside the .pf subset this project supports '
                       '(see docs/testing.md)')

    def bind(self, lineno, match):
        """Attach the pending annotation to the subroutine declared on this line."""
        proc = self.pending
        self.pending = None
        proc.name = match.group(1)
        args = [a for a in split_args(match.group(3) or '') if a]
        proc.nargs = len(args)
        if proc.kind == 'test' and proc.nargs != 0:
            self.error(lineno, f'@test subroutine {proc.name} must take no arguments '
                       '(use @mpitest(npes=[...]) for a test with an MpiTestMethod argument)')
        if proc.kind == 'mpitest' and proc.nargs != 1:
            self.error(lineno, f'MPI test {proc.name} must take exactly one argument, '
                       'class(MpiTestMethod), intent(inout) :: this')
        if proc.kind in ('before', 'after') and proc.nargs > 1:
            self.error(lineno, f'@{proc.kind} subroutine {proc.name} takes at most one argument')
        if proc.kind in ('before', 'after') and any(p.kind == proc.kind for p in self.procedures):
            self.error(lineno, f'more than one @{proc.kind} subroutine')
        self.procedures.append(proc)

    def macro_text(self, index):
        """The code of the assertion macro on line ``index`` (0-based), which must stand alone on
        that line: pFUnit 4.x matches ``@assert<Name>(...)`` only on a line ending with ``)``."""
        line = self.lines[index]
        code, _ = strip_comment(line)
        code = code.rstrip()
        name = RE_ASSERT_START.match(line).group(2)
        if code.endswith('&'):
            self.error(index + 1, f'@assert{name} continued with "&": pFUnit translates a macro '
                       'only when it is written on one line (compute long arguments into '
                       'variables first)')
        if code != line.rstrip():
            self.error(index + 1, f'comment after @assert{name}: pFUnit translates a macro only '
                       'when its line ends with ")" (put the comment on a line of its own)')
        return code

    def expand_macro(self, index):
        """Fortran lines replacing the assertion macro that starts at line ``index``."""
        lineno = index + 1
        text, last = self.macro_text(index), index
        match = RE_ASSERT_START.match(text)
        variant = match.group(2).lower()
        if variant not in ASSERTIONS:
            self.error(lineno, f'@assert{match.group(2)} is outside the supported subset '
                       f'({", ".join("@assert" + ASSERTION_NAMES[k][6:] for k in ASSERTIONS)})')
        open_at = match.end() - 1
        close_at = matching_paren(text, open_at)
        if close_at < 0:
            self.error(lineno, 'unbalanced parentheses in assertion')
        if text[close_at + 1:].strip():
            self.error(lineno, f'unexpected text after the assertion: "{text[close_at + 1:].strip()}"')
        args = split_args(text[open_at + 1:close_at])
        if any(not a for a in args):
            self.error(lineno, 'empty argument in assertion')
        positional = [a for a in args if not re.match(r'^\w+\s*=[^=]', a)]
        if len(positional) < ASSERTIONS[variant]:
            self.error(lineno, f'@assert{match.group(2)} needs at least {ASSERTIONS[variant]} '
                       'operands')
        indent = match.group(1)
        location = f'location=SourceLocation({fortran_string(self.base)}, {lineno})'
        pieces = args + [location]
        out = [f'#line {lineno} "{self.path}"']
        head = f'{indent}call {ASSERTION_NAMES[variant]}('
        out.append(head + pieces[0] + (', &' if len(pieces) > 1 else ')'))
        for k, piece in enumerate(pieces[1:], start=1):
            end = ', &' if k < len(pieces) - 1 else ')'
            out.append(f'{indent}    {piece}{end}')
        out.append(f'{indent}if (anyExceptions()) return')
        out.append(f'#line {last + 2} "{self.path}"')
        return out, last

    # ------------------------------------------------------------------ main pass
    def translate(self):
        """Return the translated module as a list of lines; fills self.procedures."""
        out = [f'#line 1 "{self.path}"']
        i = 0
        while i < len(self.lines):
            line = self.lines[i]
            lineno = i + 1
            stripped = line.lstrip()
            if stripped.startswith('@'):
                if RE_ASSERT_START.match(line):
                    if self.pending is not None:
                        self.error(lineno, 'assertion between an annotation and its subroutine')
                    expanded, last = self.expand_macro(i)
                    if out and out[-1].startswith('#line '):
                        out.pop()   # superseded by the macro's own #line
                    out.extend(expanded)
                    i = last + 1
                    continue
                match = RE_ANNOTATION.match(line)
                if not match:
                    self.error(lineno, f'cannot parse directive "{stripped}"')
                self.annotation(lineno, match)
                out.append('! ' + stripped)
                i += 1
                continue
            if self.module is None:
                match = RE_MODULE.match(line)
                if match and match.group(1).lower() != 'procedure':
                    self.module = match.group(1)
                    if self.module.lower() != self.expected_module.lower():
                        self.error(lineno, f'module {self.module} must be named as the file '
                                   f'({self.expected_module})')
            if RE_USE_FUNIT.match(line):
                self.error(lineno, 'write "use pfunit", not "use funit" (design section 8: the '
                           'tests must build against pFUnit with MPI and against pfunit-lite)')
            if self.pending is not None:
                match = RE_SUBROUTINE.match(line)
                if match:
                    self.bind(lineno, match)
                elif stripped and not stripped.startswith('!'):
                    self.error(lineno, f'@{self.pending.kind} (line {self.pending.line}) must be '
                               'followed by a subroutine statement')
            out.append(line)
            i += 1
        if self.pending is not None:
            self.error(self.pending.line, f'@{self.pending.kind} without a subroutine')
        if self.module is None:
            self.error(1, 'no module found')
        if not self.tests():
            self.error(1, 'no @test or @mpitest found')
        return out

    def tests(self):
        return [p for p in self.procedures if p.kind in ('test', 'mpitest')]

    def hook(self, kind):
        found = [p for p in self.procedures if p.kind == kind]
        return found[0] if found else None

    def driver(self):
        """Fortran lines of the driver program."""
        program = ('pf_driver_' + self.module)[:63]
        before, after = self.hook('before'), self.hook('after')
        names = [p.name for p in self.procedures]
        out = ['',
               f'!> Driver generated by pf2f90.py from {self.base}: runs every test of module',
               f'!! {self.module}, prints one line per test and a summary, exits non-zero on failure.',
               f'program {program}',
               '  use pfunit, only: MpiTestMethod, anyExceptions, pf_runner_t, pf_runner_init, &',
               '    pf_test_start, pf_test_end, pf_runner_finish',
               f'  use {self.module}, only: &']
        for k, name in enumerate(names):
            out.append(f'    {name}' + (', &' if k < len(names) - 1 else ''))
        out += ['  implicit none',
                '  type(pf_runner_t) :: pf_runner',
                '  type(MpiTestMethod) :: pf_this',
                '  logical :: pf_run',
                '',
                f'  call pf_runner_init(pf_runner, {fortran_string(self.base)})']

        def hook_call(proc):
            return f'call {proc.name}(pf_this)' if proc.nargs else f'call {proc.name}()'

        for test in self.tests():
            for npes in (test.npes if test.kind == 'mpitest' else [0]):
                call = f'call {test.name}(pf_this)' if test.kind == 'mpitest' else \
                    f'call {test.name}()'
                out.append(f'  call pf_test_start(pf_runner, pf_this, {fortran_string(test.name)}'
                           f', {npes}, pf_run)')
                out.append('  if (pf_run) then')
                if before:
                    out.append(f'    {hook_call(before)}')
                    out.append(f'    if (.not. anyExceptions()) {call}')
                else:
                    out.append(f'    {call}')
                if after:
                    out.append(f'    {hook_call(after)}')
                out.append('  end if')
                out.append('  call pf_test_end(pf_runner, pf_this)')
        out += ['  call pf_runner_finish(pf_runner)', f'end program {program}']
        return out

    def info(self):
        """One line for CMake: whether serial tests exist and the distinct npes of MPI tests."""
        tests = self.tests()
        serial = int(any(t.kind == 'test' for t in tests))
        npes = sorted({n for t in tests for n in t.npes})
        return f'serial={serial} npes={",".join(str(n) for n in npes)}'


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('source', help='the .pf file')
    parser.add_argument('-o', '--output', help='the .F90 file to write')
    parser.add_argument('--info', action='store_true',
                        help='print "serial=<0|1> npes=<list>" and exit')
    args = parser.parse_args(argv)
    try:
        translator = Translator(args.source)
        module_lines = translator.translate()
        if args.info:
            print(translator.info())
            return 0
        if not args.output:
            parser.error('-o/--output is required')
        text = '\n'.join(module_lines + translator.driver()) + '\n'
        tmp = args.output + '.tmp'
        with open(tmp, 'w', encoding='utf-8') as handle:
            handle.write(text)
        os.replace(tmp, args.output)
    except PfError as err:
        print(err, file=sys.stderr)
        return 1
    except OSError as err:
        print(f'pf2f90: {err}', file=sys.stderr)
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main())
