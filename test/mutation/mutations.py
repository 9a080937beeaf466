#!/usr/bin/env python3
"""Reads test/mutation/mutations.txt and applies, reverts or checks its mutations.

Usage: mutations.py apply|revert ID LIST SRC   one mutation on the source tree SRC
       mutations.py check LIST SRC              every mutation applies to SRC as it is: each OLD
                                                text occurs exactly once in its file, and each NEW
                                                text once after the change (the CTest mutation_list,
                                                so a change to the code cannot silently retire one)
"""
import sys


def read_list(path):
    blocks, cur = {}, None
    for line in open(path, encoding='utf-8'):
        line = line.rstrip('\n')
        if line.startswith('## '):
            ident = line[3:].split()[0]
            cur = blocks[ident] = {'what': line[3 + len(ident):].strip(), 'file': None, 'pairs': []}
        elif cur is None or not line.strip() or line.startswith('#'):
            continue
        elif line.startswith('file: '):
            cur['file'] = line[6:].strip()
        elif line.startswith('- '):
            cur['pairs'].append([line[2:], None])
        elif line.startswith('+ '):
            cur['pairs'][-1][1] = line[2:]
    return blocks


def mutate(ident, m, text, mode):
    """The text with mutation m applied (or reverted); raises ValueError when it does not apply."""
    for old, new in m['pairs']:
        a, b = (old, new) if mode == 'apply' else (new, old)
        n = text.count(a)
        if n != 1:
            raise ValueError('%s: %r occurs %d times in %s (must be once)' % (ident, a, n, m['file']))
        text = text.replace(a, b)
    if mode == 'apply':  # the revert needs each new text once, too
        for old, new in m['pairs']:
            if text.count(new) != 1:
                raise ValueError('%s: %r would occur %d times in %s (must be once)' % (ident, new, text.count(new), m['file']))
    return text


def main(argv):
    if len(argv) == 4 and argv[1] == 'check':
        blocks, src = read_list(argv[2]), argv[3]
        bad = 0
        for ident, m in blocks.items():
            try:
                if not m['file'] or not m['pairs'] or any(n is None for _, n in m['pairs']):
                    raise ValueError('%s: needs a file line and OLD/NEW pairs' % ident)
                mutate(ident, m, open(src + '/' + m['file'], encoding='utf-8').read(), 'apply')
            except (ValueError, OSError) as e:
                print(e)
                bad += 1
        print('mutation list: %d mutations, %d do not apply' % (len(blocks), bad))
        return 1 if bad else 0
    if len(argv) == 5 and argv[1] in ('apply', 'revert'):
        mode, ident, path, src = argv[1:5]
        m = read_list(path)[ident]
        f = src + '/' + m['file']
        try:
            text = mutate(ident, m, open(f, encoding='utf-8').read(), mode)
        except ValueError as e:
            sys.exit(str(e))
        open(f, 'w', encoding='utf-8').write(text)
        return 0
    sys.exit(__doc__)


if __name__ == '__main__':
    sys.exit(main(sys.argv))
