//! The hand-written Fortran module `include/rodkit.f90` must mirror the
//! cbindgen header `include/rodkit.h` (c-api.md: "ISO_C_BINDING interfaces for
//! every exported function and type"). Both files are parsed here (std only)
//! and compared:
//!
//! - functions: every prototype of the header has a `bind(c)` interface whose
//!   binding label is the C name, and every `bind(c)` interface names a
//!   prototype; same argument count, order and names; each argument's type
//!   maps (`int32_t` → `integer(c_int32_t), value`, `double*` →
//!   `real(c_double)` scalar or array without `value`, `char*` →
//!   `character(kind=c_char)` array or `type(c_ptr), value`, struct pointer →
//!   `type(<snake name>)` or `type(c_ptr), value`, …); `const` pointers are
//!   `intent(in)`, writable ones are not; return types map (`void` →
//!   subroutine);
//! - structs: a `bind(c)` derived type named in snake case
//!   (`RodkitThinTubeSpec` → `rodkit_thin_tube_spec`) with the same fields,
//!   in order, of mapped types;
//! - constants: every enumerator and every `RODKIT_` `#define` is a parameter
//!   with the same name and value (integers as `integer(c_int32_t)`, strings
//!   as character), and no stale `rodkit_*` parameter remains.
//!
//! Fortran names are case-insensitive, so a C function whose name equals a
//! macro or enumerator up to case would need another Fortran name; such a
//! rename is accepted only for such collisions, and the binding label must
//! still be the C name. (The C API avoids collisions: the ABI query is
//! `rodkit_library_abi_version`, not `rodkit_abi_version`.)
//!
//! The self-checks at the end feed the checker modified copies of both files
//! (and a small fixture with awkward formatting) and require it to report the
//! drift, so these tests cannot pass by parsing nothing.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::process::Command;

const HEADER_PATH: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/include/rodkit.h");
const MODULE_PATH: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/include/rodkit.f90");

fn read(path: &str) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("cannot read {path}: {e}"))
}

// ===========================================================================
// C header
// ===========================================================================

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Ident(String),
    Num(String),
    Str(String),
    Punct(char),
}

impl Tok {
    fn is(&self, c: char) -> bool {
        matches!(self, Tok::Punct(p) if *p == c)
    }
    fn ident(&self) -> Option<&str> {
        match self {
            Tok::Ident(s) => Some(s),
            _ => None,
        }
    }
    fn text(&self) -> String {
        match self {
            Tok::Ident(s) | Tok::Num(s) => s.clone(),
            Tok::Str(s) => format!("{s:?}"),
            Tok::Punct(c) => c.to_string(),
        }
    }
}

fn tokens_text(toks: &[Tok]) -> String {
    toks.iter().map(Tok::text).collect::<Vec<_>>().join(" ")
}

/// A C type as written: base words (`int32_t`, `RodkitThinTubeSpec`), the
/// number of `*`, whether the pointee is `const`, an optional array length.
#[derive(Clone, Debug, PartialEq)]
struct CType {
    base: String,
    ptr: usize,
    is_const: bool,
    array: Option<String>,
    funptr: bool,
}

impl CType {
    fn display(&self) -> String {
        if self.funptr {
            return "function pointer".into();
        }
        let mut s = String::new();
        if self.is_const {
            s.push_str("const ");
        }
        s.push_str(&self.base);
        for _ in 0..self.ptr {
            s.push('*');
        }
        if let Some(n) = &self.array {
            s.push_str(&format!("[{n}]"));
        }
        s
    }
}

#[derive(Clone, Debug)]
struct CParam {
    name: String,
    ty: CType,
}

#[derive(Clone, Debug)]
struct CFunction {
    name: String,
    ret: CType,
    params: Vec<CParam>,
}

#[derive(Clone, Debug)]
struct CStruct {
    name: String,
    fields: Vec<CParam>,
}

#[derive(Clone, Debug)]
struct CEnum {
    name: String,
    underlying: String,
    variants: Vec<(String, i64)>,
}

#[derive(Clone, Debug, PartialEq)]
enum CDefine {
    Int(i64),
    Str(String),
}

#[derive(Debug, Default)]
struct CHeader {
    functions: Vec<CFunction>,
    structs: Vec<CStruct>,
    enums: Vec<CEnum>,
    defines: Vec<(String, CDefine)>,
    /// typedef name → aliased type
    aliases: BTreeMap<String, CType>,
    funptr_typedefs: BTreeSet<String>,
    /// constructs the parser does not understand (reported as errors)
    unsupported: Vec<String>,
}

/// Replace comments by blanks, keeping newlines (for preprocessor lines).
fn strip_c_comments(src: &str) -> String {
    let b: Vec<char> = src.chars().collect();
    let mut out = String::with_capacity(src.len());
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c == '"' || c == '\'' {
            out.push(c);
            i += 1;
            while i < b.len() && b[i] != c && b[i] != '\n' {
                if b[i] == '\\' && i + 1 < b.len() {
                    out.push(b[i]);
                    i += 1;
                }
                out.push(b[i]);
                i += 1;
            }
            if i < b.len() {
                out.push(b[i]);
                i += 1;
            }
        } else if c == '/' && b.get(i + 1) == Some(&'/') {
            while i < b.len() && b[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && b.get(i + 1) == Some(&'*') {
            i += 2;
            while i < b.len() && !(b[i] == '*' && b.get(i + 1) == Some(&'/')) {
                if b[i] == '\n' {
                    out.push('\n');
                }
                i += 1;
            }
            i += 2;
            out.push(' ');
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

fn tokenize_c(src: &str) -> Vec<Tok> {
    let b: Vec<char> = src.chars().collect();
    let mut toks = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_alphabetic() || c == '_' {
            let s = i;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == '_') {
                i += 1;
            }
            toks.push(Tok::Ident(b[s..i].iter().collect()));
        } else if c.is_ascii_digit() {
            let s = i;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == '.') {
                i += 1;
            }
            toks.push(Tok::Num(b[s..i].iter().collect()));
        } else if c == '"' {
            let mut s = String::new();
            i += 1;
            while i < b.len() && b[i] != '"' {
                if b[i] == '\\' && i + 1 < b.len() {
                    i += 1;
                }
                s.push(b[i]);
                i += 1;
            }
            i += 1;
            toks.push(Tok::Str(s));
        } else {
            toks.push(Tok::Punct(c));
            i += 1;
        }
    }
    toks
}

/// `123`, `-4`, `(5)`, `7u`, `0x10` → value.
fn parse_c_int(text: &str) -> Option<i64> {
    let mut t = text.trim();
    while t.starts_with('(') && t.ends_with(')') {
        t = t[1..t.len() - 1].trim();
    }
    let (neg, t) = match t.strip_prefix('-') {
        Some(r) => (true, r.trim()),
        None => (false, t.strip_prefix('+').unwrap_or(t).trim()),
    };
    let t = t.trim_end_matches(['u', 'U', 'l', 'L']);
    let v = if let Some(h) = t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        i64::from_str_radix(h, 16).ok()?
    } else {
        t.parse::<i64>().ok()?
    };
    Some(if neg { -v } else { v })
}

fn parse_c_string_literal(text: &str) -> Option<String> {
    let t = text.trim();
    let inner = t.strip_prefix('"')?.strip_suffix('"')?;
    Some(inner.replace("\\\"", "\"").replace("\\\\", "\\"))
}

/// Split at top-level commas (outside (), [], {}).
fn split_top(toks: &[Tok], sep: char) -> Vec<&[Tok]> {
    let mut parts = Vec::new();
    let mut depth = 0i32;
    let mut start = 0;
    for (i, t) in toks.iter().enumerate() {
        match t {
            Tok::Punct('(' | '[' | '{') => depth += 1,
            Tok::Punct(')' | ']' | '}') => depth -= 1,
            Tok::Punct(c) if *c == sep && depth == 0 => {
                parts.push(&toks[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&toks[start..]);
    parts
}

/// Index of the bracket matching the opening one at `open`.
fn matching(toks: &[Tok], open: usize) -> Option<usize> {
    let (o, c) = match toks[open] {
        Tok::Punct('(') => ('(', ')'),
        Tok::Punct('[') => ('[', ']'),
        Tok::Punct('{') => ('{', '}'),
        _ => return None,
    };
    let mut depth = 0;
    for (i, t) in toks.iter().enumerate().skip(open) {
        if t.is(o) {
            depth += 1;
        } else if t.is(c) {
            depth -= 1;
            if depth == 0 {
                return Some(i);
            }
        }
    }
    None
}

fn parse_ctype(toks: &[Tok]) -> CType {
    let mut ty = CType { base: String::new(), ptr: 0, is_const: false, array: None, funptr: false };
    let mut words = Vec::new();
    for t in toks {
        match t {
            // `const` before the first `*` qualifies the pointee.
            Tok::Ident(w) if w == "const" && ty.ptr == 0 => ty.is_const = true,
            Tok::Ident(w) if w == "const" => {}
            Tok::Ident(w)
                if ["struct", "enum", "union", "volatile", "restrict", "extern", "static", "inline"]
                    .contains(&w.as_str()) => {}
            Tok::Ident(w) => words.push(w.clone()),
            Tok::Punct('*') => ty.ptr += 1,
            _ => {}
        }
    }
    ty.base = words.join(" ");
    ty
}

/// `type name`, `type name[N]`, `type *name`, `R (*name)(args)`.
fn parse_c_declarator(toks: &[Tok], what: &str, unsupported: &mut Vec<String>) -> Option<CParam> {
    if toks.iter().any(|t| t.is('(')) {
        // function pointer: R (*name)(...)
        let p = toks.iter().position(|t| t.is('('))?;
        if toks.get(p + 1).is_some_and(|t| t.is('*')) {
            if let Some(name) = toks.get(p + 2).and_then(Tok::ident) {
                let mut ty = parse_ctype(&toks[..p]);
                ty.funptr = true;
                ty.ptr = 0;
                return Some(CParam { name: name.to_string(), ty });
            }
        }
        unsupported.push(format!("{what}: cannot parse `{}`", tokens_text(toks)));
        return None;
    }
    let mut end = toks.len();
    let mut array = None;
    if end > 0 && toks[end - 1].is(']') {
        let open = toks.iter().rposition(|t| t.is('['))?;
        array = Some(tokens_text(&toks[open + 1..end - 1]));
        end = open;
    }
    let name = match toks[..end].last().and_then(Tok::ident) {
        Some(n) if end >= 2 => n.to_string(),
        _ => {
            unsupported.push(format!("{what}: cannot parse `{}`", tokens_text(toks)));
            return None;
        }
    };
    let mut ty = parse_ctype(&toks[..end - 1]);
    ty.array = array;
    Some(CParam { name, ty })
}

// Over 120 lines: one pass over the header's items; this parser and its
// hand-written module go when the module is generated from the header
// (issue 20).
fn parse_header(src: &str) -> CHeader {
    let mut h = CHeader::default();
    let text = strip_c_comments(src);
    // Preprocessor lines (with backslash continuations) out; #define kept.
    let mut code = String::new();
    let mut lines = text.lines();
    while let Some(line) = lines.next() {
        let mut line = line.to_string();
        while line.trim_end().ends_with('\\') {
            let l = line.trim_end();
            line = format!("{} {}", &l[..l.len() - 1], lines.next().unwrap_or(""));
        }
        let t = line.trim_start();
        if let Some(directive) = t.strip_prefix('#') {
            let directive = directive.trim_start();
            if let Some(rest) = directive.strip_prefix("define") {
                let rest = rest.trim_start();
                let name_len = rest.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(rest.len());
                let (name, value) = rest.split_at(name_len);
                if !name.starts_with("RODKIT_") {
                    continue;
                }
                if value.starts_with('(') {
                    h.unsupported.push(format!("function-like macro `{name}` has no Fortran equivalent"));
                    continue;
                }
                let value = value.trim();
                if value.is_empty() {
                    continue; // include guard
                }
                if let Some(v) = parse_c_int(value) {
                    h.defines.push((name.to_string(), CDefine::Int(v)));
                } else if let Some(s) = parse_c_string_literal(value) {
                    h.defines.push((name.to_string(), CDefine::Str(s)));
                } else {
                    h.unsupported.push(format!("#define {name} {value}: cannot evaluate"));
                }
            }
            code.push('\n');
        } else {
            code.push_str(&line);
            code.push('\n');
        }
    }
    let toks = tokenize_c(&code);

    // Top-level declarations, skipping `extern "C" {` … `}` (C++ linkage).
    let mut decls: Vec<Vec<Tok>> = Vec::new();
    let mut cur = Vec::new();
    let mut depth = 0i32;
    let mut i = 0;
    while i < toks.len() {
        let t = &toks[i];
        if depth == 0 && cur.is_empty() {
            if t.ident() == Some("extern")
                && matches!(toks.get(i + 1), Some(Tok::Str(_)))
                && toks.get(i + 2).is_some_and(|t| t.is('{'))
            {
                i += 3;
                continue;
            }
            if t.is('}') {
                i += 1;
                continue;
            }
        }
        match t {
            Tok::Punct('(' | '{' | '[') => depth += 1,
            Tok::Punct(')' | '}' | ']') => depth -= 1,
            _ => {}
        }
        if depth == 0 && t.is(';') {
            decls.push(std::mem::take(&mut cur));
        } else {
            cur.push(t.clone());
        }
        i += 1;
    }
    if !cur.is_empty() {
        h.unsupported.push(format!("unterminated declaration `{}`", tokens_text(&cur)));
    }

    for d in decls {
        if d.is_empty() {
            continue;
        }
        let (typedef, body) = if d[0].ident() == Some("typedef") { (true, &d[1..]) } else { (false, &d[..]) };
        let has_brace = body.iter().any(|t| t.is('{'));
        let kw = body.first().and_then(Tok::ident).unwrap_or("");
        if has_brace && (kw == "struct" || kw == "union") {
            let open = body.iter().position(|t| t.is('{')).unwrap();
            let close = matching(body, open).unwrap_or(body.len() - 1);
            let tag = body[1..open].iter().filter_map(Tok::ident).next_back().map(String::from);
            let alias = body[close + 1..].iter().filter_map(Tok::ident).next_back().map(String::from);
            let Some(name) = tag.clone().or(alias.clone()) else {
                h.unsupported.push(format!("anonymous struct `{}`", tokens_text(&d)));
                continue;
            };
            if kw == "union" {
                h.unsupported.push(format!("union {name} has no Fortran interoperable equivalent"));
                continue;
            }
            let mut fields = Vec::new();
            for f in split_top(&body[open + 1..close], ';') {
                if f.is_empty() {
                    continue;
                }
                if f.iter().any(|t| t.is(':')) {
                    h.unsupported.push(format!("bit field in struct {name}: `{}`", tokens_text(f)));
                    continue;
                }
                if let Some(p) = parse_c_declarator(f, &format!("struct {name}"), &mut h.unsupported) {
                    fields.push(p);
                }
            }
            if let (Some(a), true) = (&alias, typedef) {
                if *a != name {
                    h.aliases.insert(
                        a.clone(),
                        CType { base: name.clone(), ptr: 0, is_const: false, array: None, funptr: false },
                    );
                }
            }
            h.structs.push(CStruct { name, fields });
        } else if has_brace && kw == "enum" {
            let open = body.iter().position(|t| t.is('{')).unwrap();
            let close = matching(body, open).unwrap_or(body.len() - 1);
            let tag = body.get(1).and_then(Tok::ident).map(String::from);
            let colon = body[..open].iter().position(|t| t.is(':'));
            let underlying = colon.map(|c| parse_ctype(&body[c + 1..open]).base).unwrap_or_else(|| "int".into());
            let alias = body[close + 1..].iter().filter_map(Tok::ident).next_back().map(String::from);
            let Some(name) = tag.or(alias) else {
                h.unsupported.push(format!("anonymous enum `{}`", tokens_text(&d)));
                continue;
            };
            let mut variants = Vec::new();
            let mut next = 0i64;
            for v in split_top(&body[open + 1..close], ',') {
                if v.is_empty() {
                    continue;
                }
                let Some(vname) = v[0].ident() else {
                    h.unsupported.push(format!("enum {name}: cannot parse `{}`", tokens_text(v)));
                    continue;
                };
                let value = if v.len() > 1 {
                    if !v[1].is('=') {
                        h.unsupported.push(format!("enum {name}: cannot parse `{}`", tokens_text(v)));
                        continue;
                    }
                    let expr: String = v[2..].iter().map(Tok::text).collect();
                    match parse_c_int(&expr) {
                        Some(x) => x,
                        None => {
                            h.unsupported.push(format!("enum {name}: cannot evaluate `{vname} = {expr}`"));
                            continue;
                        }
                    }
                } else {
                    next
                };
                next = value + 1;
                variants.push((vname.to_string(), value));
            }
            h.enums.push(CEnum { name, underlying, variants });
        } else if typedef {
            if body.iter().any(|t| t.is('(')) {
                let p = body.iter().position(|t| t.is('(')).unwrap();
                match (body.get(p + 1), body.get(p + 2).and_then(Tok::ident)) {
                    (Some(t), Some(name)) if t.is('*') => {
                        h.funptr_typedefs.insert(name.to_string());
                    }
                    _ => h.unsupported.push(format!("typedef `{}`", tokens_text(&d))),
                }
                continue;
            }
            let Some(alias) = body.last().and_then(Tok::ident) else {
                h.unsupported.push(format!("typedef `{}`", tokens_text(&d)));
                continue;
            };
            let target = parse_ctype(&body[..body.len() - 1]);
            if target.base != alias || target.ptr != 0 {
                // `typedef enum X X;` and `typedef struct X X;` are no-ops
                let previous = h.aliases.insert(alias.to_string(), target.clone());
                if let Some(prev) = previous {
                    let (a, b) = (h.resolve(&prev), h.resolve(&target));
                    if a != b {
                        h.unsupported.push(format!(
                            "conflicting typedefs of {alias}: {} and {}",
                            a.display(),
                            b.display()
                        ));
                    }
                }
            }
        } else if body.iter().any(|t| t.is('(')) {
            let p = body.iter().position(|t| t.is('(')).unwrap();
            let close = matching(body, p).unwrap_or(body.len() - 1);
            let name = match p.checked_sub(1).and_then(|q| body[q].ident()) {
                Some(n) if p >= 2 => n.to_string(),
                _ => {
                    h.unsupported.push(format!("declaration `{}`", tokens_text(&d)));
                    continue;
                }
            };
            if close + 1 != body.len() {
                h.unsupported
                    .push(format!("{name}: unexpected `{}` after the argument list", tokens_text(&body[close + 1..])));
            }
            let ret = parse_ctype(&body[..p - 1]);
            let inner = &body[p + 1..close];
            let mut params = Vec::new();
            let is_void = inner.is_empty() || (inner.len() == 1 && inner[0].ident() == Some("void"));
            if !is_void {
                for a in split_top(inner, ',') {
                    let Some(mut param) = parse_c_declarator(a, &name, &mut h.unsupported) else {
                        continue;
                    };
                    if param.ty.array.take().is_some() {
                        param.ty.ptr += 1; // `double k[]` is `double *k`
                    }
                    params.push(param);
                }
            }
            h.functions.push(CFunction { name, ret, params });
        } else if kw == "struct" && body.len() == 2 {
            // forward declaration of an opaque type
        } else {
            h.unsupported.push(format!("top-level declaration `{}`", tokens_text(&d)));
        }
    }
    h
}

/// What a C type is, after typedefs and enums are resolved.
#[derive(Clone, Debug, PartialEq)]
enum CKind {
    /// interoperable scalar: the Fortran type, e.g. `integer(c_int32_t)`
    Scalar(String),
    Char,
    Void,
    Struct(String),
    FunPtr,
    /// unknown (opaque) type name: only usable behind a pointer
    Opaque(String),
    Unsupported(String),
}

fn scalar_fortran_type(base: &str) -> Option<&'static str> {
    Some(match base {
        "int8_t" => "integer(c_int8_t)",
        "int16_t" => "integer(c_int16_t)",
        "int32_t" => "integer(c_int32_t)",
        "int64_t" => "integer(c_int64_t)",
        "int" => "integer(c_int)",
        "short" => "integer(c_short)",
        "long" => "integer(c_long)",
        "long long" => "integer(c_long_long)",
        "size_t" => "integer(c_size_t)",
        "ptrdiff_t" => "integer(c_ptrdiff_t)",
        "intptr_t" => "integer(c_intptr_t)",
        "double" => "real(c_double)",
        "float" => "real(c_float)",
        "bool" | "_Bool" => "logical(c_bool)",
        _ => return None,
    })
}

impl CHeader {
    /// Follow typedefs and enum tags down to a base type (pointers add up).
    fn resolve(&self, ty: &CType) -> CType {
        let mut t = ty.clone();
        for _ in 0..16 {
            if t.funptr {
                break;
            }
            if let Some(e) = self.enums.iter().find(|e| e.name == t.base) {
                t.base = e.underlying.clone();
                continue;
            }
            if self.funptr_typedefs.contains(&t.base) {
                t.funptr = true;
                break;
            }
            if let Some(a) = self.aliases.get(&t.base) {
                let ptr = t.ptr + a.ptr;
                let is_const = if t.ptr == 0 { t.is_const || a.is_const } else { t.is_const };
                let array = t.array.clone();
                t = CType { base: a.base.clone(), ptr, is_const, array, funptr: a.funptr };
                continue;
            }
            break;
        }
        t
    }

    fn kind_of_base(&self, t: &CType) -> CKind {
        if t.funptr {
            return CKind::FunPtr;
        }
        if let Some(f) = scalar_fortran_type(&t.base) {
            return CKind::Scalar(f.to_string());
        }
        match t.base.as_str() {
            "char" => CKind::Char,
            "void" => CKind::Void,
            b if b.starts_with("uint") || b.starts_with("unsigned") => CKind::Unsupported(format!(
                "`{b}` is unsigned: Fortran has no unsigned integers (c-api.md: use int64_t)"
            )),
            b if self.structs.iter().any(|s| s.name == b) => CKind::Struct(b.to_string()),
            b if b.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') && !b.is_empty() => {
                CKind::Opaque(b.to_string())
            }
            b => CKind::Unsupported(format!("unknown C type `{b}`")),
        }
    }

    fn int_define_names(&self) -> impl Iterator<Item = &str> {
        self.defines
            .iter()
            .map(|(n, _)| n.as_str())
            .chain(self.enums.iter().flat_map(|e| e.variants.iter().map(|(n, _)| n.as_str())))
    }
}

/// `RodkitThinTubeSpec` → `rodkit_thin_tube_spec` (`RodkitABIInfo` → `rodkit_abi_info`).
fn snake_case(name: &str) -> String {
    let c: Vec<char> = name.chars().collect();
    let mut out = String::new();
    for i in 0..c.len() {
        let ch = c[i];
        if ch.is_ascii_uppercase() && i > 0 {
            let prev = c[i - 1];
            let next_lower = c.get(i + 1).is_some_and(|n| n.is_ascii_lowercase());
            if prev.is_ascii_lowercase() || prev.is_ascii_digit() || (prev.is_ascii_uppercase() && next_lower) {
                out.push('_');
            }
        }
        out.push(ch.to_ascii_lowercase());
    }
    out
}

// ===========================================================================
// Fortran module
// ===========================================================================

/// One statement after joining continuation lines and dropping comments:
/// the original text and an ASCII-lowercased copy (same byte offsets).
#[derive(Clone, Debug)]
struct Stmt {
    line: usize,
    orig: String,
    lc: String,
}

/// Free-form source → statements: `!` comments (outside strings) removed,
/// `&` continuations joined, `;` separated statements split.
fn fortran_statements(src: &str) -> Vec<Stmt> {
    let mut out = Vec::new();
    let mut pending = String::new();
    let mut pending_line = 0;
    let mut quote: Option<char> = None; // open string carried over a continuation
    for (n, raw) in src.lines().enumerate() {
        // Remove the comment, tracking quotes.
        let mut code = String::new();
        let mut q = quote;
        let mut chars = raw.chars().peekable();
        let mut first_nonblank = true;
        while let Some(c) = chars.next() {
            if first_nonblank && !c.is_whitespace() {
                first_nonblank = false;
                if !pending.is_empty() && c == '&' {
                    continue; // leading & of a continuation line
                }
            }
            match q {
                Some(qc) => {
                    code.push(c);
                    if c == qc {
                        if chars.peek() == Some(&qc) {
                            code.push(chars.next().unwrap());
                        } else {
                            q = None;
                        }
                    }
                }
                None => {
                    if c == '!' {
                        break;
                    }
                    if c == '"' || c == '\'' {
                        q = Some(c);
                    }
                    code.push(c);
                }
            }
        }
        let trimmed = code.trim_end();
        if trimmed.trim_start().is_empty() {
            continue; // blank or comment line (also between continuation lines)
        }
        let (body, continued) = match trimmed.strip_suffix('&') {
            Some(b) => (b.to_string(), true),
            None => (trimmed.to_string(), false),
        };
        if pending.is_empty() {
            pending_line = n + 1;
            pending.push_str(body.trim_start());
        } else {
            if !pending.ends_with(' ') && q.is_none() {
                pending.push(' ');
            }
            pending.push_str(if quote.is_some() { &body } else { body.trim_start() });
        }
        quote = if continued { q } else { None };
        if continued {
            continue;
        }
        for part in split_outside_quotes(&pending, ';') {
            let orig = part.trim().to_string();
            if !orig.is_empty() {
                let lc = orig.to_ascii_lowercase();
                out.push(Stmt { line: pending_line, orig, lc });
            }
        }
        pending.clear();
    }
    out
}

fn split_outside_quotes(s: &str, sep: char) -> Vec<String> {
    let mut parts = Vec::new();
    let mut cur = String::new();
    let mut q: Option<char> = None;
    for c in s.chars() {
        match q {
            Some(qc) => {
                if c == qc {
                    q = None;
                }
                cur.push(c);
            }
            None if c == sep => parts.push(std::mem::take(&mut cur)),
            None => {
                if c == '"' || c == '\'' {
                    q = Some(c);
                }
                cur.push(c);
            }
        }
    }
    parts.push(cur);
    parts
}

/// Split at top-level commas (outside parentheses and strings).
fn split_commas(s: &str) -> Vec<String> {
    let mut parts = Vec::new();
    let mut cur = String::new();
    let mut depth = 0i32;
    let mut q: Option<char> = None;
    for c in s.chars() {
        match q {
            Some(qc) => {
                if c == qc {
                    q = None;
                }
                cur.push(c);
            }
            None => match c {
                '"' | '\'' => {
                    q = Some(c);
                    cur.push(c);
                }
                '(' | '[' => {
                    depth += 1;
                    cur.push(c);
                }
                ')' | ']' => {
                    depth -= 1;
                    cur.push(c);
                }
                ',' if depth == 0 => parts.push(std::mem::take(&mut cur).trim().to_string()),
                _ => cur.push(c),
            },
        }
    }
    if !cur.trim().is_empty() || !parts.is_empty() {
        parts.push(cur.trim().to_string());
    }
    parts
}

/// Byte offset of the `)` matching the `(` at `open`.
fn close_paren(s: &str, open: usize) -> Option<usize> {
    let mut depth = 0;
    let mut q: Option<u8> = None;
    for (i, &c) in s.as_bytes().iter().enumerate().skip(open) {
        match q {
            Some(qc) => {
                if c == qc {
                    q = None;
                }
            }
            None => match c {
                b'"' | b'\'' => q = Some(c),
                b'(' => depth += 1,
                b')' => {
                    depth -= 1;
                    if depth == 0 {
                        return Some(i);
                    }
                }
                _ => {}
            },
        }
    }
    None
}

/// Top-level `::` position (outside strings and parentheses).
fn find_double_colon(s: &str) -> Option<usize> {
    let b = s.as_bytes();
    let mut depth = 0;
    let mut q: Option<u8> = None;
    for i in 0..b.len() {
        let c = b[i];
        match q {
            Some(qc) => {
                if c == qc {
                    q = None;
                }
            }
            None => match c {
                b'"' | b'\'' => q = Some(c),
                b'(' => depth += 1,
                b')' => depth -= 1,
                b':' if depth == 0 && b.get(i + 1) == Some(&b':') => return Some(i),
                _ => {}
            },
        }
    }
    None
}

fn strip_spaces(s: &str) -> String {
    s.chars().filter(|c| !c.is_whitespace()).collect()
}

/// A Fortran type spec, normalised: `integer(c_int32_t)`, `real(c_double)`,
/// `character(c_char)` (+ len), `type(rodkit_thin_tube_spec)`, `type(c_ptr)`.
#[derive(Clone, Debug, PartialEq)]
struct FType {
    name: String,
    char_len: Option<String>,
}

fn normalize_typespec(spec: &str) -> FType {
    let s = strip_spaces(&spec.to_ascii_lowercase());
    if s == "doubleprecision" {
        return FType { name: "double precision".into(), char_len: None };
    }
    let (kw, inner) = match s.find('(') {
        Some(p) if s.ends_with(')') => (&s[..p], Some(&s[p + 1..s.len() - 1])),
        _ => (s.as_str(), None),
    };
    match (kw, inner) {
        ("character", inner) => {
            let mut kind = None;
            let mut len = None;
            if let Some(inner) = inner {
                for (i, item) in split_commas(inner).iter().enumerate() {
                    if let Some(k) = item.strip_prefix("kind=") {
                        kind = Some(k.to_string());
                    } else if let Some(l) = item.strip_prefix("len=") {
                        len = Some(l.to_string());
                    } else if i == 0 {
                        len = Some(item.clone());
                    } else {
                        kind = Some(item.clone());
                    }
                }
            }
            let kind = kind.unwrap_or_else(|| "default".into());
            FType { name: format!("character({kind})"), char_len: Some(len.unwrap_or_else(|| "1".into())) }
        }
        (kw, Some(inner)) => {
            let inner = inner.strip_prefix("kind=").unwrap_or(inner);
            FType { name: format!("{kw}({inner})"), char_len: None }
        }
        (kw, None) => FType { name: kw.to_string(), char_len: None },
    }
}

/// One declared entity: its type, attributes, array spec, initialiser.
#[derive(Clone, Debug)]
struct FDecl {
    ty: FType,
    attrs: BTreeSet<String>,
    intent: Option<String>,
    dims: Option<String>,
    init: Option<String>,
    line: usize,
}

impl FDecl {
    fn has(&self, attr: &str) -> bool {
        self.attrs.contains(attr)
    }
}

const TYPE_KEYWORDS: [&str; 7] =
    ["integer", "real", "logical", "character", "complex", "double precision", "doubleprecision"];

/// A type declaration statement → its entities, or None if the statement is
/// not one (a derived-type definition `type, bind(c) :: x` is not).
fn parse_declaration(st: &Stmt) -> Option<Vec<(String, FDecl)>> {
    let lc = st.lc.as_str();
    let starts_kw = TYPE_KEYWORDS.iter().any(|k| {
        lc.starts_with(k)
            && lc[k.len()..].chars().next().is_some_and(|c| c == '(' || c == ',' || c == ':' || c == ' ' || c == '*')
    });
    let starts_type = (lc.starts_with("type") || lc.starts_with("class")) && {
        let rest = lc.trim_start_matches("type").trim_start_matches("class").trim_start();
        rest.starts_with('(')
    };
    if !starts_kw && !starts_type {
        return None;
    }
    let (left, right, orig_right) = match find_double_colon(lc) {
        Some(p) => (&lc[..p], &lc[p + 2..], &st.orig[p + 2..]),
        None => {
            // `integer(c_int32_t) x` / `real x`: the type spec ends after the
            // keyword and its optional parenthesised selector.
            let kw_end = TYPE_KEYWORDS
                .iter()
                .chain(["type", "class"].iter())
                .filter(|k| lc.starts_with(*k))
                .map(|k| k.len())
                .max()?;
            let rest = &lc[kw_end..];
            let sel_end = if rest.trim_start().starts_with('(') {
                let open = kw_end + rest.find('(')?;
                close_paren(lc, open)? + 1
            } else {
                kw_end
            };
            (&lc[..sel_end], &lc[sel_end..], &st.orig[sel_end..])
        }
    };
    let mut parts = split_commas(left);
    if parts.is_empty() {
        return None;
    }
    let ty = normalize_typespec(&parts.remove(0));
    let mut attrs = BTreeSet::new();
    let mut intent = None;
    let mut attr_dims = None;
    for a in parts {
        let a = strip_spaces(&a);
        if let Some(i) = a.strip_prefix("intent(").and_then(|r| r.strip_suffix(')')) {
            intent = Some(i.to_string());
        } else if let Some(d) = a.strip_prefix("dimension(").and_then(|r| r.strip_suffix(')')) {
            attr_dims = Some(d.to_string());
        } else {
            attrs.insert(a);
        }
    }
    let mut out = Vec::new();
    let lc_entities = split_commas(right);
    let orig_entities = split_commas(orig_right);
    for (e, eo) in lc_entities.iter().zip(orig_entities.iter()) {
        let name_len = e.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(e.len());
        let name = e[..name_len].to_string();
        if name.is_empty() {
            continue;
        }
        let mut rest = e[name_len..].trim_start();
        let mut dims = attr_dims.clone();
        if rest.starts_with('(') {
            let close = close_paren(rest, 0)?;
            dims = Some(strip_spaces(&rest[1..close]));
            rest = rest[close + 1..].trim_start();
        }
        let init = rest.strip_prefix('=').filter(|r| !r.starts_with('>')).map(|_| {
            let p = eo.find('=').unwrap();
            eo[p + 1..].trim().to_string()
        });
        out.push((
            name,
            FDecl { ty: ty.clone(), attrs: attrs.clone(), intent: intent.clone(), dims, init, line: st.line },
        ));
    }
    Some(out)
}

#[derive(Clone, Debug)]
struct FProc {
    name: String,
    line: usize,
    is_function: bool,
    binding: Option<String>,
    dummies: Vec<String>,
    result: Option<String>,
    prefix_type: Option<FType>,
    decls: BTreeMap<String, FDecl>,
}

#[derive(Clone, Debug)]
struct FTypeDef {
    name: String,
    line: usize,
    bind_c: bool,
    components: Vec<(String, FDecl)>,
}

#[derive(Debug, Default)]
struct FModule {
    name: Option<String>,
    procs: Vec<FProc>,
    types: Vec<FTypeDef>,
    parameters: Vec<(String, FDecl)>,
    problems: Vec<String>,
}

/// Word `kw` at a top-level position of `lc` (outside parentheses/strings).
fn find_keyword(lc: &str, kw: &str) -> Option<usize> {
    let b = lc.as_bytes();
    let mut depth = 0;
    let mut q: Option<u8> = None;
    let is_word = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    for i in 0..b.len() {
        let c = b[i];
        match q {
            Some(qc) => {
                if c == qc {
                    q = None;
                }
                continue;
            }
            None => match c {
                b'"' | b'\'' => {
                    q = Some(c);
                    continue;
                }
                b'(' => depth += 1,
                b')' => depth -= 1,
                _ => {}
            },
        }
        if depth == 0
            && lc[i..].starts_with(kw)
            && (i == 0 || !is_word(b[i - 1]))
            && !b.get(i + kw.len()).is_some_and(|&c| is_word(c))
        {
            return Some(i);
        }
    }
    None
}

/// `[prefix] function name(args) [bind(c, name="x")] [result(r)]` or
/// `subroutine name[(args)] [bind(...)]`.
fn parse_proc_header(st: &Stmt) -> Option<Result<FProc, String>> {
    let lc = st.lc.as_str();
    let (pos, is_function) = match (find_keyword(lc, "function"), find_keyword(lc, "subroutine")) {
        (Some(p), _) => (p, true),
        (None, Some(p)) => (p, false),
        _ => return None,
    };
    let prefix = lc[..pos].trim();
    if prefix.starts_with("end") || prefix.contains("::") || prefix.contains('=') {
        return None;
    }
    let kw_len = if is_function { "function".len() } else { "subroutine".len() };
    let after = &lc[pos + kw_len..];
    let name_start = pos + kw_len + (after.len() - after.trim_start().len());
    let name_len =
        lc[name_start..].find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(lc.len() - name_start);
    let name = lc[name_start..name_start + name_len].to_string();
    if name.is_empty() {
        return Some(Err(format!("line {}: cannot parse `{}`", st.line, st.orig)));
    }
    let mut rest_at = name_start + name_len;
    let mut dummies = Vec::new();
    let trimmed = lc[rest_at..].trim_start();
    if trimmed.starts_with('(') {
        let open = rest_at + (lc[rest_at..].len() - trimmed.len());
        let Some(close) = close_paren(lc, open) else {
            return Some(Err(format!("line {}: unbalanced parentheses in `{}`", st.line, st.orig)));
        };
        dummies = split_commas(&lc[open + 1..close]).into_iter().filter(|d| !d.is_empty()).collect();
        rest_at = close + 1;
    }
    let suffix_lc = &lc[rest_at..];
    let suffix_orig = &st.orig[rest_at..];
    let mut binding = None;
    if let Some(b) = find_keyword(suffix_lc, "bind") {
        let open = b + suffix_lc[b..].find('(')?;
        let close = close_paren(suffix_lc, open)?;
        let inner_orig = &suffix_orig[open + 1..close];
        let items = split_commas(inner_orig);
        let label = items.iter().find_map(|it| {
            let (k, v) = it.split_once('=')?;
            (k.trim().eq_ignore_ascii_case("name")).then(|| v.trim().trim_matches(['"', '\'']).trim().to_string())
        });
        binding = Some(label.unwrap_or_else(|| name.clone()));
    }
    let mut result = None;
    if let Some(r) = find_keyword(suffix_lc, "result") {
        let open = r + suffix_lc[r..].find('(')?;
        let close = close_paren(suffix_lc, open)?;
        result = Some(strip_spaces(&suffix_lc[open + 1..close]));
    }
    let prefix_type = {
        let words: String = prefix.to_string();
        let cleaned = ["pure", "elemental", "recursive", "impure", "module"]
            .iter()
            .fold(words, |w, k| w.split_whitespace().filter(|x| x != k).collect::<Vec<_>>().join(" "));
        (!cleaned.is_empty()).then(|| normalize_typespec(&cleaned))
    };
    Some(Ok(FProc { name, line: st.line, is_function, binding, dummies, result, prefix_type, decls: BTreeMap::new() }))
}

fn is_end(lc: &str, what: &str) -> bool {
    let s = strip_spaces(lc);
    s == "end" || s.starts_with(&format!("end{what}"))
}

fn parse_module(src: &str) -> FModule {
    let mut m = FModule::default();
    let mut in_interface = false;
    let mut abstract_interface = false;
    let mut proc: Option<FProc> = None;
    let mut tdef: Option<FTypeDef> = None;
    for st in fortran_statements(src) {
        let lc = st.lc.as_str();
        let nospace = strip_spaces(lc);
        if let Some(p) = proc.as_mut() {
            if is_end(lc, if p.is_function { "function" } else { "subroutine" }) {
                let p = proc.take().unwrap();
                if !abstract_interface {
                    m.procs.push(p);
                }
            } else if let Some(entities) = parse_declaration(&st) {
                for (n, d) in entities {
                    if p.decls.insert(n.clone(), d).is_some() {
                        m.problems.push(format!("line {}: `{n}` declared twice in {}", st.line, p.name));
                    }
                }
            }
            continue;
        }
        if let Some(t) = tdef.as_mut() {
            if nospace.starts_with("endtype") {
                m.types.push(tdef.take().unwrap());
            } else if let Some(entities) = parse_declaration(&st) {
                t.components.extend(entities);
            } else if nospace != "sequence" && !nospace.starts_with("private") && nospace != "contains" {
                m.problems.push(format!("line {}: unexpected `{}` in type {}", st.line, st.orig, t.name));
            }
            continue;
        }
        if m.name.is_none() {
            if let Some(rest) = lc.strip_prefix("module ") {
                m.name = Some(rest.trim().to_string());
            }
            continue;
        }
        if nospace == "contains" || nospace.starts_with("endmodule") {
            break; // module procedures follow: not part of the C interface
        }
        if nospace.starts_with("abstractinterface") {
            in_interface = true;
            abstract_interface = true;
            continue;
        }
        if lc.starts_with("interface") && (lc.len() == 9 || !lc.as_bytes()[9].is_ascii_alphanumeric()) {
            in_interface = true;
            abstract_interface = false;
            continue;
        }
        if nospace.starts_with("endinterface") {
            in_interface = false;
            continue;
        }
        if in_interface {
            match parse_proc_header(&st) {
                Some(Ok(p)) => proc = Some(p),
                Some(Err(e)) => m.problems.push(e),
                None => {
                    if !nospace.starts_with("moduleprocedure") && !nospace.starts_with("procedure") {
                        m.problems.push(format!("line {}: unexpected `{}` in an interface block", st.line, st.orig));
                    }
                }
            }
            continue;
        }
        // derived-type definition: `type, bind(c) :: name`, `type :: name`, `type name`
        let is_type_definition = lc.starts_with("type") && {
            let r = &lc[4..];
            r.starts_with(',')
                || r.trim_start().starts_with("::")
                || (r.starts_with(' ') && !r.trim_start().starts_with('('))
        };
        if is_type_definition {
            let (attrs, name) = match find_double_colon(lc) {
                Some(p) => (strip_spaces(&lc[4..p]), strip_spaces(&lc[p + 2..])),
                None => (String::new(), lc[4..].trim().to_string()),
            };
            let bind_c = attrs.split(',').any(|a| a == "bind(c)");
            tdef = Some(FTypeDef { name, line: st.line, bind_c, components: Vec::new() });
            continue;
        }
        if let Some(entities) = parse_declaration(&st) {
            for (n, d) in entities {
                if d.has("parameter") {
                    m.parameters.push((n, d));
                }
            }
        }
    }
    if proc.is_some() || tdef.is_some() || in_interface {
        m.problems.push("unterminated interface, procedure or type definition".into());
    }
    m
}

/// Fortran integer constant: `-3`, `(+4)`, `7_c_int32_t`.
fn parse_fortran_int(text: &str) -> Option<i64> {
    let mut t = strip_spaces(text);
    while t.starts_with('(') && t.ends_with(')') {
        t = t[1..t.len() - 1].to_string();
    }
    let t = match t.find('_') {
        Some(p) => t[..p].to_string(),
        None => t,
    };
    t.parse::<i64>().ok()
}

fn parse_fortran_string(text: &str) -> Option<String> {
    let t = text.trim();
    let q = t.chars().next().filter(|c| *c == '"' || *c == '\'')?;
    let inner = t.strip_prefix(q)?.strip_suffix(q)?;
    Some(inner.replace(&format!("{q}{q}"), &q.to_string()))
}

// ===========================================================================
// The comparison
// ===========================================================================

fn describe(d: &FDecl) -> String {
    let mut s = d.ty.name.clone();
    if let Some(l) = &d.ty.char_len {
        if l != "1" {
            s.push_str(&format!(" len={l}"));
        }
    }
    for a in &d.attrs {
        s.push_str(", ");
        s.push_str(a);
    }
    if let Some(i) = &d.intent {
        s.push_str(&format!(", intent({i})"));
    }
    if let Some(dims) = &d.dims {
        s.push_str(&format!(" ({dims})"));
    }
    s
}

/// Array spec usable for a C pointer: assumed size `*` or explicit shape
/// (`3`, `ldk,*`); not assumed shape `:` (a descriptor, not a pointer).
fn pointer_compatible_dims(dims: &Option<String>) -> bool {
    match dims {
        None => true,
        Some(d) => d.split(',').all(|x| !(x.starts_with(':') || x.ends_with(':'))),
    }
}

/// Does the Fortran dummy argument `d` bind the C parameter type `c`?
fn check_argument(h: &CHeader, c: &CType, d: &FDecl) -> Result<(), String> {
    let c = h.resolve(c);
    let value = d.has("value");
    let scalar = d.dims.is_none();
    for bad in ["pointer", "allocatable", "optional"] {
        if d.has(bad) {
            return Err(format!("`{bad}` dummies are not C pointers in Fortran 2008"));
        }
    }
    let is_cptr_value = d.ty.name == "type(c_ptr)" && value && scalar;
    if c.ptr == 0 {
        let want = match h.kind_of_base(&c) {
            CKind::Scalar(f) => f,
            CKind::FunPtr => "type(c_funptr)".into(),
            CKind::Struct(s) => format!("type({})", snake_case(&s)),
            CKind::Char => "character(c_char)".into(),
            CKind::Unsupported(why) => return Err(why),
            CKind::Void | CKind::Opaque(_) => return Err(format!("`{}` cannot be passed by value", c.display())),
        };
        if d.ty.name != want || !value || !scalar {
            return Err(format!("C `{}` must be `{want}, value` (scalar)", c.display()));
        }
        return Ok(());
    }
    // A pointer: `type(c_ptr), value` always binds it correctly.
    if is_cptr_value {
        return Ok(());
    }
    let want = if c.ptr >= 2 {
        Some("type(c_ptr)".to_string()) // T** (e.g. a handle out-parameter)
    } else {
        match h.kind_of_base(&c) {
            CKind::Scalar(f) => Some(f),
            CKind::Struct(s) => Some(format!("type({})", snake_case(&s))),
            CKind::Char => Some("character(c_char)".into()),
            CKind::FunPtr => Some("type(c_funptr)".into()),
            CKind::Void | CKind::Opaque(_) => None,
            CKind::Unsupported(why) => return Err(why),
        }
    };
    let alternatives = match &want {
        Some(w) => format!("`{w}` without `value`, or `type(c_ptr), value`"),
        None => "`type(c_ptr), value`".into(),
    };
    let Some(want) = want else {
        return Err(format!("C `{}` must be {alternatives}", c.display()));
    };
    if d.ty.name != want || value {
        return Err(format!("C `{}` must be {alternatives}", c.display()));
    }
    if !pointer_compatible_dims(&d.dims) {
        return Err("assumed-shape arrays `(:)` are not C pointers in Fortran 2008: use `(*)`".into());
    }
    if want == "character(c_char)" {
        if scalar {
            return Err(format!(
                "C `{}` must be a `character(kind=c_char)` array `(*)` (or `type(c_ptr), value`)",
                c.display()
            ));
        }
        if d.ty.char_len.as_deref() != Some("1") {
            return Err("a C string is an array of `character(kind=c_char)` of length 1".into());
        }
    }
    match (c.is_const, d.intent.as_deref()) {
        (true, Some("in")) => {}
        (true, _) => return Err(format!("C `{}` is read-only: declare it `intent(in)`", c.display())),
        (false, Some("in")) => {
            return Err(format!(
                "C `{}` is written by rodkit: `intent(in)` would let the compiler assume it unchanged",
                c.display()
            ))
        }
        (false, _) => {}
    }
    Ok(())
}

fn check_result(h: &CHeader, c: &CType, ty: &FType) -> Result<(), String> {
    let c = h.resolve(c);
    let want = if c.ptr > 0 {
        "type(c_ptr)".to_string()
    } else {
        match h.kind_of_base(&c) {
            CKind::Scalar(f) => f,
            CKind::Struct(s) => format!("type({})", snake_case(&s)),
            CKind::FunPtr => "type(c_funptr)".into(),
            CKind::Unsupported(why) => return Err(why),
            _ => return Err(format!("C return type `{}` has no Fortran function result", c.display())),
        }
    };
    if ty.name != want {
        return Err(format!("C returns `{}`: the function result must be `{want}`, not `{}`", c.display(), ty.name));
    }
    Ok(())
}

fn check_field(h: &CHeader, c: &CType, d: &FDecl) -> Result<(), String> {
    let c = h.resolve(c);
    let want = if c.ptr > 0 {
        "type(c_ptr)".to_string()
    } else {
        match h.kind_of_base(&c) {
            CKind::Scalar(f) => f,
            CKind::Struct(s) => format!("type({})", snake_case(&s)),
            CKind::Char => "character(c_char)".into(),
            CKind::FunPtr => "type(c_funptr)".into(),
            CKind::Unsupported(why) => return Err(why),
            _ => return Err(format!("C field type `{}` has no Fortran equivalent", c.display())),
        }
    };
    if d.ty.name != want {
        return Err(format!("C `{}` must be `{want}`", c.display()));
    }
    if !d.attrs.is_empty() {
        return Err(format!("unexpected attributes {:?}", d.attrs));
    }
    let want_dims = c.array.as_ref().map(|n| {
        let n = n.replace(' ', "");
        h.defines
            .iter()
            .find(|(name, _)| *name == n)
            .and_then(|(_, v)| if let CDefine::Int(x) = v { Some(x.to_string()) } else { None })
            .unwrap_or(n)
    });
    let got_dims = d.dims.as_ref().map(|x| x.to_ascii_lowercase());
    if want_dims.as_ref().map(|x| x.to_ascii_lowercase()) != got_dims {
        return Err(format!("C array length {:?}, Fortran dimension {:?}", c.array, d.dims));
    }
    Ok(())
}

/// Every difference between the header and the module, as readable lines.
// Over 120 lines, as `parse_header` (issue 20 replaces both).
fn compare(header_src: &str, module_src: &str) -> Vec<String> {
    let h = parse_header(header_src);
    let m = parse_module(module_src);
    let mut errors: Vec<String> = Vec::new();
    for u in &h.unsupported {
        errors.push(format!("rodkit.h: {u} (extend tests/fortran_interface.rs if this is intended)"));
    }
    for p in &m.problems {
        errors.push(format!("rodkit.f90: {p}"));
    }
    if m.name.as_deref() != Some("rodkit") {
        errors.push(format!("rodkit.f90: expected `module rodkit`, found {:?}", m.name));
    }
    if h.functions.is_empty() || m.procs.is_empty() {
        errors.push(format!(
            "parsed {} C prototypes and {} Fortran interfaces: the parsers found nothing",
            h.functions.len(),
            m.procs.len()
        ));
    }

    // Names that collide, up to case, with a function's name: those are the
    // only functions allowed another Fortran name.
    let constant_names: BTreeSet<String> = h
        .int_define_names()
        .map(|s| s.to_ascii_lowercase())
        .chain(h.structs.iter().map(|s| snake_case(&s.name)))
        .collect();

    // ---- functions ----
    let mut by_label: BTreeMap<String, &FProc> = BTreeMap::new();
    for p in &m.procs {
        match &p.binding {
            None => errors.push(format!("rodkit.f90 line {}: interface `{}` has no bind(c)", p.line, p.name)),
            Some(label) => {
                if by_label.insert(label.clone(), p).is_some() {
                    errors.push(format!("rodkit.f90 line {}: two interfaces bind `{label}`", p.line));
                }
            }
        }
    }
    let c_names: BTreeSet<&str> = h.functions.iter().map(|f| f.name.as_str()).collect();
    for (label, p) in &by_label {
        if !c_names.contains(label.as_str()) {
            errors.push(format!(
                "rodkit.f90 line {}: interface `{}` binds `{label}`, which rodkit.h does not declare (stale or misspelt)",
                p.line, p.name
            ));
        }
    }
    for f in &h.functions {
        let Some(p) = by_label.get(&f.name) else {
            errors.push(format!("{}: no Fortran interface with bind(c, name=\"{}\") in rodkit.f90", f.name, f.name));
            continue;
        };
        let lname = f.name.to_ascii_lowercase();
        if p.name != lname && !constant_names.contains(&lname) {
            errors.push(format!(
                "{}: the Fortran interface is named `{}`; it must be `{}` (a rename is only allowed when the C name collides, up to case, with a constant)",
                f.name, p.name, lname
            ));
        }
        let c_args: Vec<String> = f.params.iter().map(|a| a.name.to_ascii_lowercase()).collect();
        if c_args != p.dummies {
            errors.push(format!(
                "{}: arguments differ: C ({}) vs Fortran ({})",
                f.name,
                c_args.join(", "),
                p.dummies.join(", ")
            ));
        }
        for (i, a) in f.params.iter().enumerate() {
            let Some(dname) = p.dummies.get(i) else {
                continue;
            };
            let Some(decl) = p.decls.get(dname) else {
                errors.push(format!("{}: dummy argument `{dname}` is not declared in the interface", f.name));
                continue;
            };
            if *dname != a.name.to_ascii_lowercase() {
                continue; // already reported
            }
            if let Err(e) = check_argument(&h, &a.ty, decl) {
                errors.push(format!(
                    "{}: argument `{}`: {e}; Fortran has `{}` (line {})",
                    f.name,
                    a.name,
                    describe(decl),
                    decl.line
                ));
            }
        }
        let ret = h.resolve(&f.ret);
        let is_void = ret.ptr == 0 && ret.base == "void";
        if is_void {
            if p.is_function {
                errors.push(format!("{}: C returns void: the interface must be a subroutine", f.name));
            }
        } else if !p.is_function {
            errors.push(format!("{}: C returns `{}`: the interface must be a function", f.name, ret.display()));
        } else {
            let result_name = p.result.clone().unwrap_or_else(|| p.name.clone());
            let ty = p.decls.get(&result_name).map(|d| d.ty.clone()).or_else(|| p.prefix_type.clone());
            match ty {
                None => errors.push(format!("{}: the function result `{result_name}` has no declared type", f.name)),
                Some(ty) => {
                    if let Err(e) = check_result(&h, &f.ret, &ty) {
                        errors.push(format!("{}: {e}", f.name));
                    }
                }
            }
        }
    }

    // ---- structs ----
    let c_structs: BTreeMap<String, &CStruct> = h.structs.iter().map(|s| (snake_case(&s.name), s)).collect();
    for t in &m.types {
        if t.bind_c && !c_structs.contains_key(&t.name) {
            errors.push(format!("rodkit.f90 line {}: bind(c) type `{}` matches no struct of rodkit.h", t.line, t.name));
        }
    }
    for (snake, s) in &c_structs {
        let Some(t) = m.types.iter().find(|t| t.name == *snake) else {
            errors.push(format!("struct {}: no derived type `{snake}` in rodkit.f90", s.name));
            continue;
        };
        if !t.bind_c {
            errors.push(format!("struct {}: type `{snake}` must be declared `type, bind(c) :: {snake}`", s.name));
        }
        let c_fields: Vec<String> = s.fields.iter().map(|f| f.name.to_ascii_lowercase()).collect();
        let f_fields: Vec<String> = t.components.iter().map(|(n, _)| n.clone()).collect();
        if c_fields != f_fields {
            errors.push(format!(
                "struct {}: fields differ (order matters): C ({}) vs Fortran ({})",
                s.name,
                c_fields.join(", "),
                f_fields.join(", ")
            ));
            continue;
        }
        for (cf, (_, d)) in s.fields.iter().zip(&t.components) {
            if let Err(e) = check_field(&h, &cf.ty, d) {
                errors.push(format!(
                    "struct {}: field `{}`: {e}; Fortran has `{}` (line {})",
                    s.name,
                    cf.name,
                    describe(d),
                    d.line
                ));
            }
        }
    }

    // ---- constants ----
    let params: BTreeMap<String, &FDecl> = m.parameters.iter().map(|(n, d)| (n.clone(), d)).collect();
    let mut expected: Vec<(String, CDefine, String)> = Vec::new(); // name, value, fortran type
    for (name, v) in &h.defines {
        let ty = match v {
            CDefine::Int(x) if i32::try_from(*x).is_ok() => "integer(c_int32_t)".to_string(),
            CDefine::Int(_) => "integer(c_int64_t)".to_string(),
            CDefine::Str(_) => "character".to_string(),
        };
        expected.push((name.clone(), v.clone(), ty));
    }
    for e in &h.enums {
        let ty = match h.kind_of_base(&CType {
            base: e.underlying.clone(),
            ptr: 0,
            is_const: false,
            array: None,
            funptr: false,
        }) {
            CKind::Scalar(f) => f,
            _ => "integer(c_int)".into(),
        };
        for (name, v) in &e.variants {
            expected.push((name.clone(), CDefine::Int(*v), ty.clone()));
        }
    }
    if expected.is_empty() {
        errors.push("rodkit.h: parsed no enumerators and no RODKIT_ macros".into());
    }
    let expected_names: BTreeSet<String> = expected.iter().map(|(n, _, _)| n.to_ascii_lowercase()).collect();
    for (name, value, ty) in &expected {
        let Some(d) = params.get(&name.to_ascii_lowercase()) else {
            errors.push(format!("{name}: no parameter `{name}` in rodkit.f90"));
            continue;
        };
        let init = d.init.clone().unwrap_or_default();
        match value {
            CDefine::Int(v) => {
                if d.ty.name != *ty {
                    errors.push(format!(
                        "{name}: must be `{ty}, parameter`, Fortran has `{}` (line {})",
                        d.ty.name, d.line
                    ));
                }
                match parse_fortran_int(&init) {
                    Some(x) if x == *v => {}
                    Some(x) => errors.push(format!("{name}: C value {v}, Fortran value {x} (line {})", d.line)),
                    None => {
                        errors.push(format!("{name}: cannot evaluate the Fortran value `{init}` (line {})", d.line))
                    }
                }
            }
            CDefine::Str(s) => {
                if !d.ty.name.starts_with("character") {
                    errors.push(format!("{name}: a C string: must be a character parameter (line {})", d.line));
                }
                match parse_fortran_string(&init) {
                    Some(x) if x == *s => {}
                    other => errors.push(format!("{name}: C value {s:?}, Fortran value {other:?} (line {})", d.line)),
                }
            }
        }
    }
    for (name, d) in &params {
        if name.starts_with("rodkit_") && !expected_names.contains(name) {
            errors.push(format!(
                "rodkit.f90 line {}: parameter `{name}` matches no enumerator or RODKIT_ macro of rodkit.h (stale?)",
                d.line
            ));
        }
    }
    errors
}

fn assert_agree(header: &str, module: &str) {
    let errors = compare(header, module);
    assert!(
        errors.is_empty(),
        "include/rodkit.f90 has drifted from include/rodkit.h ({} problems); update the Fortran module:\n  - {}",
        errors.len(),
        errors.join("\n  - ")
    );
}

// ===========================================================================
// Tests
// ===========================================================================

#[test]
fn fortran_module_matches_header() {
    let header = read(HEADER_PATH);
    let module = read(MODULE_PATH);
    assert_agree(&header, &module);
    // And the comparison really covered the header.
    let h = parse_header(&header);
    let m = parse_module(&module);
    assert!(h.functions.len() >= 10, "parsed only {} C functions", h.functions.len());
    assert_eq!(m.procs.len(), h.functions.len());
    assert!(h.structs.iter().any(|s| s.name == "RodkitThinTubeSpec" && s.fields.len() == 7));
    assert!(h.enums.iter().any(|e| e.name == "RodkitStatus" && e.variants.contains(&("RODKIT_STATUS_OK".into(), 0))));
    assert!(h.defines.iter().any(|(n, _)| n == "RODKIT_ABI_VERSION"));
}

/// The module compiles cleanly as Fortran 2008 (gfortran is a test
/// prerequisite, see `.ci/deps`), so the parsed text is real Fortran.
#[test]
fn fortran_module_compiles_cleanly() {
    let dir = std::env::temp_dir().join(format!("rodkit-fortran-interface-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = Command::new("gfortran")
        .args(["-std=f2008", "-Wall", "-Wextra", "-Werror", "-fsyntax-only", "-J"])
        .arg(&dir)
        .arg(Path::new(MODULE_PATH))
        .current_dir(&dir)
        .output()
        .unwrap_or_else(|e| panic!("cannot run gfortran (install it: .ci/deps): {e}"));
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        out.status.success(),
        "gfortran -std=f2008 -Wall -Wextra -Werror rejects include/rodkit.f90:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Apply a textual change, insisting that the pattern exists (otherwise the
/// self-check would test nothing).
fn mutate(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "self-check pattern not found (update the self-check): {from:?}");
    text.replacen(from, to, 1)
}

fn assert_caught(what: &str, header: &str, module: &str, needle: &str) {
    let errors = compare(header, module);
    assert!(
        errors.iter().any(|e| e.contains(needle)),
        "self-check `{what}`: the checker did not report drift mentioning {needle:?}; it reported: {errors:#?}"
    );
}

#[test]
fn checker_catches_drift_in_the_module() {
    let h = read(HEADER_PATH);
    let f = read(MODULE_PATH);
    let cases: Vec<(&str, String, &str)> = vec![
        (
            "argument removed",
            mutate(
                &f,
                "rodkit_thin_tube_coupling_stiffness(spec, k, ldk)",
                "rodkit_thin_tube_coupling_stiffness(spec, k)",
            ),
            "rodkit_thin_tube_coupling_stiffness: arguments differ",
        ),
        (
            "arguments swapped",
            mutate(&f, "rodkit_thin_tube_stretch_twist(spec, s, lds)", "rodkit_thin_tube_stretch_twist(s, spec, lds)"),
            "rodkit_thin_tube_stretch_twist: arguments differ",
        ),
        (
            "wrong enumerator value",
            mutate(&f, "RODKIT_STATUS_ERR_NOT_FINITE = -3", "RODKIT_STATUS_ERR_NOT_FINITE = -33"),
            "C value -3, Fortran value -33",
        ),
        (
            "wrong version value",
            mutate(&f, "RODKIT_ABI_VERSION = 2", "RODKIT_ABI_VERSION = 3"),
            "RODKIT_ABI_VERSION: C value 2",
        ),
        (
            "enumerator missing",
            mutate(&f, "RODKIT_WINDING_NEITHER = 0", "RODKIT_WINDING_NONE = 0"),
            "RODKIT_WINDING_NEITHER: no parameter",
        ),
        (
            "value attribute dropped",
            mutate(&f, "integer(c_int64_t), value :: capacity", "integer(c_int64_t) :: capacity"),
            "argument `capacity`",
        ),
        (
            "wrong integer kind",
            mutate(&f, "integer(c_int64_t), value :: ldk", "integer(c_int32_t), value :: ldk"),
            "argument `ldk`",
        ),
        (
            "intent(in) on an output array",
            mutate(&f, "real(c_double), intent(inout) :: k(*)", "real(c_double), intent(in) :: k(*)"),
            "argument `k`",
        ),
        (
            "assumed shape instead of assumed size",
            mutate(&f, "real(c_double), intent(inout) :: s(*)", "real(c_double), intent(inout) :: s(:)"),
            "argument `s`",
        ),
        (
            "struct fields swapped",
            mutate(&f, "        real(c_double) :: e1\n", "        real(c_double) :: e2_tmp\n")
                .replacen("real(c_double) :: e2\n", "real(c_double) :: e1\n", 1)
                .replacen("e2_tmp", "e2", 1),
            "struct RodkitThinTubeSpec: fields differ",
        ),
        (
            "struct field type",
            mutate(&f, "integer(c_int32_t) :: winding", "real(c_double) :: winding"),
            "field `winding`",
        ),
        (
            "binding label misspelt",
            mutate(&f, "name=\"rodkit_version\"", "name=\"rodkit_versoin\""),
            "rodkit_version: no Fortran interface",
        ),
        (
            "result type",
            mutate(
                &f,
                "type(c_ptr) :: message\n        end function rodkit_status_string",
                "integer(c_int32_t) :: message\n        end function rodkit_status_string",
            ),
            "rodkit_status_string: C returns",
        ),
        (
            "interface removed",
            {
                let a = f.find("        function rodkit_version(").expect("self-check: rodkit_version interface");
                let b = f.find("end function rodkit_version").expect("self-check: end of rodkit_version")
                    + "end function rodkit_version".len();
                format!("{}{}", &f[..a], &f[b..])
            },
            "rodkit_version: no Fortran interface",
        ),
        (
            "unneeded rename",
            mutate(&f, "function rodkit_thin_tube_free_response(spec", "function rodkit_tube_free_response(spec"),
            "must be `rodkit_thin_tube_free_response`",
        ),
        (
            "bind(c) dropped from a type",
            mutate(&f, "type, bind(c) :: rodkit_free_tube_response", "type :: rodkit_free_tube_response"),
            "struct RodkitFreeTubeResponse: type `rodkit_free_tube_response` must be declared",
        ),
    ];
    for (what, module, needle) in &cases {
        assert_ne!(module, &f, "self-check `{what}` did not change the module");
        assert_caught(what, &h, module, needle);
    }
}

#[test]
fn checker_catches_drift_in_the_header() {
    let h = read(HEADER_PATH);
    let f = read(MODULE_PATH);
    let end_of_functions = "#ifdef __cplusplus\n}  // extern \"C\"";
    let cases: Vec<(&str, String, &str)> = vec![
        (
            "new function (multi-line prototype)",
            mutate(&h, end_of_functions, &format!("int32_t rodkit_tube_new_thing(const struct RodkitThinTubeSpec *spec,\n                              double *out);\n\n{end_of_functions}")),
            "rodkit_tube_new_thing: no Fortran interface",
        ),
        ("function removed", mutate(&h, "int32_t rodkit_library_abi_version(void);", ""), "binds `rodkit_library_abi_version`, which rodkit.h does not declare"),
        (
            "argument added",
            mutate(&h, "int32_t rodkit_version(int32_t *major, int32_t *minor, int32_t *patch);", "int32_t rodkit_version(int32_t *major, int32_t *minor, int32_t *patch, int64_t flags);"),
            "rodkit_version: arguments differ",
        ),
        (
            "argument made const",
            mutate(&h, "double *k,", "const double *k,"),
            "argument `k`: C `const double*` is read-only",
        ),
        ("new enumerator", mutate(&h, "  RODKIT_WINDING_OVERWINDS = 1,\n", "  RODKIT_WINDING_OVERWINDS = 1,\n  RODKIT_WINDING_BOTH = 2,\n"), "RODKIT_WINDING_BOTH: no parameter"),
        ("enumerator renumbered", mutate(&h, "RODKIT_STATUS_ERR_NOT_CONVERGED = -9", "RODKIT_STATUS_ERR_NOT_CONVERGED = -19"), "C value -19"),
        ("new macro", mutate(&h, "#define RODKIT_ABI_VERSION 2", "#define RODKIT_ABI_VERSION 2\n#define RODKIT_MAX_NODES 4096"), "RODKIT_MAX_NODES: no parameter"),
        ("version string", mutate(&h, "#define RODKIT_VERSION_STRING \"0.1.0\"", "#define RODKIT_VERSION_STRING \"0.2.0\""), "RODKIT_VERSION_STRING: C value \"0.2.0\""),
        (
            "new struct field",
            mutate(&h, "  int32_t winding;\n", "  int32_t winding;\n  // new\n  double energy;\n"),
            "struct RodkitFreeTubeResponse: fields differ",
        ),
        (
            "unsigned argument",
            mutate(&h, "int64_t capacity", "uint64_t capacity"),
            "unsigned",
        ),
    ];
    for (what, header, needle) in &cases {
        assert_ne!(header, &h, "self-check `{what}` did not change the header");
        assert_caught(what, header, &f, needle);
    }
}

/// Formatting the real files do not (yet) use: `/* */` comments, `#if`
/// blocks, an opaque handle with `new`/`free`, a callback typedef, a fixed
/// array field, an auto-numbered enum; on the Fortran side upper case,
/// continuation lines with leading `&`, `;`, `!` inside strings, attributes
/// in `dimension(...)`, a result declared through the function prefix.
const FIXTURE_H: &str = r#"
#define RODKIT_VERSION_MAJOR 2   /* major */
#define RODKIT_NAME "ro!d"
#define RODKIT_H_INTERNAL
typedef struct RodkitRod RodkitRod;
typedef int32_t (*RodkitProgressFn)(const struct RodkitProgress *progress, void *user_data);
enum RodkitMode
#if defined(__cplusplus) || __STDC_VERSION__ >= 202311L
  : int32_t
#endif
 {
  RODKIT_MODE_A = 3, // three
  RODKIT_MODE_B,
};
typedef int32_t RodkitMode;
typedef struct RodkitProgress {
  int64_t step;
  double values[3];
  RodkitMode mode;
} RodkitProgress;
#ifdef __cplusplus
extern "C" {
#endif
int32_t rodkit_rod_new(const struct RodkitProgress *spec,
                       RodkitRod **out);
void rodkit_rod_free(RodkitRod *rod);
int32_t rodkit_rod_run(RodkitRod *rod, RodkitProgressFn progress, void *user_data,
                       const char *label, bool verbose);
double rodkit_rod_energy(const RodkitRod *rod);
#ifdef __cplusplus
}  // extern "C"
#endif
"#;

const FIXTURE_F90: &str = r#"
MODULE RODKIT
  USE, INTRINSIC :: ISO_C_BINDING
  IMPLICIT NONE
  INTEGER(C_INT32_T), PARAMETER :: RODKIT_VERSION_MAJOR = 2_c_int32_t
  CHARACTER(LEN=*), PARAMETER :: RODKIT_NAME = 'ro!d'  ! a "!" in a string
  integer(kind=c_int32_t), parameter :: rodkit_mode_a = 3, &
                                        rodkit_mode_b = 4
  TYPE, BIND(C) :: RODKIT_PROGRESS
    INTEGER(C_INT64_T) :: STEP
    REAL(C_DOUBLE), DIMENSION(3) :: VALUES
    INTEGER(C_INT32_T) :: MODE
  END TYPE RODKIT_PROGRESS
  INTERFACE
    FUNCTION RODKIT_ROD_NEW(SPEC, OUT) RESULT(ST) &
        BIND(C, NAME='rodkit_rod_new')
      IMPORT; IMPLICIT NONE
      TYPE(RODKIT_PROGRESS), INTENT(IN) :: SPEC
      TYPE(C_PTR), INTENT(OUT) :: OUT
      INTEGER(C_INT32_T) :: ST
    END FUNCTION
    subroutine rodkit_rod_free(rod) bind(c, name="rodkit_rod_free")
      import :: c_ptr
      type(c_ptr), value :: rod
    end subroutine rodkit_rod_free
    integer(c_int32_t) function rodkit_rod_run(rod, progress, user_data, &
      & label, verbose) bind(c, name="rodkit_rod_run")
      import
      type(c_ptr), value :: rod
      type(c_funptr), value :: progress
      type(c_ptr), value :: user_data
      character(kind=c_char), dimension(*), intent(in) :: label
      logical(c_bool), value :: verbose
    end function rodkit_rod_run
    real(c_double) function rodkit_rod_energy(rod) bind(c, name="rodkit_rod_energy")
      import
      type(c_ptr), value :: rod
    end function
  END INTERFACE
CONTAINS
  SUBROUTINE HELPER()
    INTEGER, PARAMETER :: RODKIT_LOCAL = 1
  END SUBROUTINE
END MODULE RODKIT
"#;

#[test]
fn checker_handles_awkward_formatting() {
    let errors = compare(FIXTURE_H, FIXTURE_F90);
    assert!(errors.is_empty(), "the fixture pair should agree:\n{errors:#?}");
    let h = parse_header(FIXTURE_H);
    assert_eq!(h.functions.len(), 4);
    assert_eq!(h.enums[0].variants, vec![("RODKIT_MODE_A".to_string(), 3), ("RODKIT_MODE_B".to_string(), 4)]);
    assert_eq!(parse_module(FIXTURE_F90).procs.len(), 4);

    let cases = [
        (
            "continued dummy dropped",
            mutate(FIXTURE_F90, "& label, verbose)", "& label)"),
            "rodkit_rod_run: arguments differ",
        ),
        (
            "auto-numbered enumerator",
            mutate(FIXTURE_F90, "rodkit_mode_b = 4", "rodkit_mode_b = 5"),
            "RODKIT_MODE_B: C value 4",
        ),
        (
            "callback as c_ptr",
            mutate(FIXTURE_F90, "type(c_funptr), value :: progress", "type(c_ptr), value :: progress"),
            "argument `progress`",
        ),
        (
            "handle out-parameter intent(in)",
            mutate(FIXTURE_F90, "TYPE(C_PTR), INTENT(OUT) :: OUT", "TYPE(C_PTR), INTENT(IN) :: OUT"),
            "argument `out`",
        ),
        (
            "array field length",
            mutate(FIXTURE_F90, "DIMENSION(3) :: VALUES", "DIMENSION(4) :: VALUES"),
            "field `values`",
        ),
        ("string constant", mutate(FIXTURE_F90, "'ro!d'", "'rod'"), "RODKIT_NAME"),
        (
            "subroutine for a function",
            mutate(
                FIXTURE_F90,
                "real(c_double) function rodkit_rod_energy",
                "integer(c_int32_t) function rodkit_rod_energy",
            ),
            "rodkit_rod_energy: C returns",
        ),
        (
            "string as a scalar",
            mutate(
                FIXTURE_F90,
                "character(kind=c_char), dimension(*), intent(in) :: label",
                "character(kind=c_char), intent(in) :: label",
            ),
            "argument `label`",
        ),
        (
            "stale parameter",
            mutate(FIXTURE_F90, "rodkit_mode_b = 4", "rodkit_mode_b = 4, rodkit_mode_c = 5"),
            "`rodkit_mode_c` matches no enumerator",
        ),
    ];
    for (what, module, needle) in &cases {
        assert_caught(what, FIXTURE_H, module, needle);
    }
}
