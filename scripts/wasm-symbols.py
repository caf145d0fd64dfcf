#!/usr/bin/env python3
"""Symbol-name lengths in the library's wasm objects — a guard for the wasm test binary.

    python3 scripts/wasm-symbols.py TARGET/wasm32-unknown-unknown/web/deps/libmocapseg.rlib

rustc's LTO reads an upstream rlib's objects back with the `object` crate, whose wasm reader (wasmparser) refuses a
name longer than 100,000 bytes; rustc then stops with "failed to get bitcode from object file for LTO (Invalid Wasm
linking symbol)" — with nothing saying which symbol. The page's own module links (it is the crate being compiled, never
read back), so only `make test-wasm` and `make bench-wasm` broke. The long names are leptos views' drop glue: a
component's whole view tree is one static type and its mangled name grows with every row or panel added. The cure is
`.into_any()` at a big view's sub-trees (see `src/app/timeline/lines.rs`).

Prints the longest symbol of the library and the components it spells; exits 1 over the reader's limit and warns
above WARN so the next addition is seen before it breaks the build.
"""
import re
import sys

LIMIT = 100_000  # wasmparser's MAX_WASM_STRING_SIZE
WARN = 60_000


def leb(data, i):
    value = shift = 0
    while True:
        byte = data[i]
        i += 1
        value |= (byte & 0x7F) << shift
        shift += 7
        if byte < 0x80:
            return value, i


def ar_members(data):
    """The members of a System V / GNU archive (the rlib): (name, bytes)."""
    if not data.startswith(b"!<arch>\n"):
        raise ValueError("not an ar archive")
    i, long_names = 8, b""
    while i + 60 <= len(data):
        header = data[i:i + 60]
        name = header[:16].decode("ascii", "replace").strip()
        size = int(header[48:58].decode("ascii").strip())
        body = data[i + 60:i + 60 + size]
        if name == "//":
            long_names = body
        elif name.startswith("/") and name[1:].isdigit():
            start = int(name[1:])
            name = long_names[start:long_names.index(b"/\n", start)].decode("utf-8", "replace")
        yield name.rstrip("/"), body
        i += 60 + size + (size & 1)


def symbol_names(obj):
    """Every named symbol of a wasm object's `linking` section (symbol table subsection)."""
    if obj[:4] != b"\0asm":
        return
    i = 8
    while i < len(obj):
        section = obj[i]
        size, i = leb(obj, i + 1)
        end = i + size
        if section == 0:
            name_len, j = leb(obj, i)
            if obj[j:j + name_len] == b"linking":
                j += name_len
                _, j = leb(obj, j)  # version
                while j < end:
                    sub = obj[j]
                    sub_size, j = leb(obj, j + 1)
                    sub_end = j + sub_size
                    if sub == 8:  # WASM_SYMBOL_TABLE
                        count, k = leb(obj, j)
                        for _ in range(count):
                            kind = obj[k]
                            flags, k = leb(obj, k + 1)
                            if kind in (0, 2, 4, 5):  # function, global, event, table
                                _, k = leb(obj, k)
                                if not flags & 0x10 or flags & 0x40:  # defined, or an explicit name
                                    n, k = leb(obj, k)
                                    yield obj[k:k + n]
                                    k += n
                            elif kind == 1:  # data
                                n, k = leb(obj, k)
                                yield obj[k:k + n]
                                k += n
                                if not flags & 0x10:
                                    for _ in range(3):
                                        _, k = leb(obj, k)
                            elif kind == 3:  # section
                                _, k = leb(obj, k)
                            else:
                                return
                    j = sub_end
        i = end


def main(argv):
    if len(argv) != 2:
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    path = argv[1]
    try:
        data = open(path, "rb").read()
    except OSError as e:
        print(f"wasm-symbols: cannot read {path}: {e.strerror}", file=sys.stderr)
        return 2
    longest, where = b"", ""
    for member, body in ar_members(data):
        for name in symbol_names(body):
            if len(name) > len(longest):
                longest, where = name, member
    text = longest.decode("utf-8", "replace")
    components = sorted(set(re.findall(r"mocapseg\.\.(?:[a-z_]+\.\.)*__component_[a-z_]+", text)))
    spelled = ", ".join(c.replace("..", "::").replace("__component_", "") for c in components) or "none named"
    print(f"wasm-symbols: longest symbol {len(longest):,} bytes (limit {LIMIT:,}) in {where}; components in it: {spelled}")
    if len(longest) > LIMIT:
        print(
            "wasm-symbols: error: rustc's LTO cannot read this object back, so the wasm test binary will not link "
            "(\"Invalid Wasm linking symbol\"). Type-erase the big view's sub-trees with `.into_any()`.",
            file=sys.stderr,
        )
        return 1
    if len(longest) > WARN:
        print(f"wasm-symbols: warning: over {WARN:,} bytes — the next rows added to that view may break the wasm tests")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
