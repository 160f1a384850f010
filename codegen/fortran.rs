//! Generates the Fortran 2008 module `rodkit` (include/rodkit.f90) from
//! cbindgen's own view of the C API (its `Bindings`: functions, structs,
//! enums, typedefs, with their documentation), so the module and the header
//! cannot drift: every C declaration is written once, in Rust.
//!
//! Mapping (c-api.md: int32_t statuses, int64_t counts, double arrays,
//! opaque handles, #[repr(C)] parameter structs):
//! - a scalar passed by value → `VALUE`; an enum → integer(c_int32_t);
//! - a pointer to an opaque handle, or `void *` → type(c_ptr), value;
//!   a pointer to a pointer (an out handle) → type(c_ptr), intent(out);
//! - a function pointer → type(c_funptr), value (and each callback typedef
//!   becomes an abstract interface, for `procedure(...)` declarations);
//! - `const char *` / `char *` → character(kind=c_char) :: name(*);
//! - a pointer to a number or a struct is a scalar (`const` → intent(in),
//!   otherwise intent(out)) unless the function's doc comment lists it as an
//!   array with `cbindgen:fortran-arrays=[a, b]` (cbindgen keeps that line
//!   out of the header): then name(*), intent(in) or intent(inout) (a
//!   caller's array with padding rows keeps what rodkit does not write).
//! - `cbindgen:fortran-result=name` names a function's result variable
//!   (`status` for int32_t, `message` for strings, otherwise).
//!
//! Unsigned integers, unions and tagged enums have no Fortran counterpart in
//! this ABI: generation fails with the declaration's name, so a new C
//! function that Fortran cannot call does not ship silently.

use cbindgen::ir::{
    ConstExpr, Documentation, Enum, Function, IntKind, ItemContainer, Literal, PrimitiveType, Struct, Type,
};
use cbindgen::Bindings;
use std::collections::{BTreeSet, HashMap, HashSet};
use std::fmt::Write as _;

/// The version macros the header carries (build.rs), as module parameters.
pub struct Versions {
    pub major: String,
    pub minor: String,
    pub patch: String,
    pub string: String,
    pub abi: i32,
}

/// What a C type name refers to.
#[derive(Clone, Copy, PartialEq)]
enum Named {
    Opaque,
    Struct,
    Enum,
    Callback,
}

struct Gen {
    names: HashMap<String, Named>,
    /// iso_c_binding names the whole module uses.
    kinds: BTreeSet<&'static str>,
}

const WIDTH: usize = 100;

pub fn generate(bindings: &Bindings, v: &Versions, procedures: &str) -> Result<String, String> {
    let mut names = HashMap::new();
    for item in &bindings.items {
        let (name, kind) = match item {
            ItemContainer::OpaqueItem(o) => (o.export_name.clone(), Named::Opaque),
            ItemContainer::Struct(s) => (s.export_name.clone(), Named::Struct),
            ItemContainer::Enum(e) => (e.export_name.clone(), Named::Enum),
            ItemContainer::Typedef(t) if matches!(t.aliased, Type::FuncPtr { .. }) => {
                (t.export_name.clone(), Named::Callback)
            }
            ItemContainer::Typedef(t) => {
                return Err(format!("typedef {}: only callback typedefs are mapped", t.export_name))
            }
            ItemContainer::Union(u) => return Err(format!("union {}: no Fortran mapping", u.export_name)),
            ItemContainer::Constant(c) => {
                return Err(format!("constant {}: not expected in the header", c.export_name))
            }
            ItemContainer::Static(s) => return Err(format!("static {}: not expected in the header", s.export_name)),
        };
        names.insert(name, kind);
    }
    let mut g = Gen { names, kinds: BTreeSet::new() };
    let mut body = String::new();
    g.versions(&mut body, v);
    for item in &bindings.items {
        if let ItemContainer::Enum(e) = item {
            g.enumeration(&mut body, e)?;
        }
    }
    for item in &bindings.items {
        if let ItemContainer::Struct(s) = item {
            g.structure(&mut body, s)?;
        }
    }
    let callbacks: Vec<_> = bindings
        .items
        .iter()
        .filter_map(|i| match i {
            ItemContainer::Typedef(t) => Some(t),
            _ => None,
        })
        .collect();
    if !callbacks.is_empty() {
        body.push_str(&rule("Callback types: the procedures rodkit calls back (pass them with c_funloc)."));
        body.push_str("    abstract interface\n");
        for t in callbacks {
            let Type::FuncPtr { ret, args, .. } = &t.aliased else { unreachable!() };
            let args: Vec<(String, Type)> = args
                .iter()
                .enumerate()
                .map(|(i, (n, ty))| (n.clone().unwrap_or_else(|| format!("arg{}", i + 1)), ty.clone()))
                .collect();
            body.push('\n');
            doc(&mut body, &t.documentation, 8);
            g.procedure(&mut body, &fortran_name(&t.export_name), None, ret, &args, &[], None)
                .map_err(|e| format!("callback {}: {e}", t.export_name))?;
        }
        body.push_str("    end interface\n\n");
    }
    body.push_str(&rule("Functions (one interface per C function, in the header's order)."));
    body.push_str("    interface\n");
    for f in &bindings.functions {
        g.function(&mut body, f).map_err(|e| format!("{}: {e}", f.path.name()))?;
    }
    body.push_str("    end interface\n\ncontains\n\n");
    body.push_str(procedures.trim_end());
    body.push_str("\n\nend module rodkit\n");

    // The procedures use these whatever the interfaces need.
    for k in ["c_int32_t", "c_int64_t", "c_char", "c_ptr", "c_null_char", "c_associated", "c_f_pointer"] {
        g.kinds.insert(k);
    }
    let mut out = String::from(PREAMBLE);
    out.push_str("module rodkit\n");
    let kinds: Vec<&str> = g.kinds.iter().copied().collect();
    out.push_str(&wrap("    use, intrinsic :: iso_c_binding, only: ", &kinds, "        "));
    out.push_str("    implicit none\n    private :: c_string_to_fortran\n\n");
    out.push_str(&body);
    Ok(out)
}

const PREAMBLE: &str = "\
!
! rodkit: mechanics of elastic tubes and rods, Fortran 2008 interface.
!
! GENERATED by build.rs (codegen/fortran.rs) from the same definitions as
! include/rodkit.h: do not edit. Regenerate both with
! `RODKIT_WRITE_HEADER=1 cargo build` (the test suite fails when either is
! stale). The comments are the header's: read NULL as c_null_ptr, and an
! array index k[i + j*ldk] (0-based, C) as k(i+1, j+1) of k(ldk, *).
!
! Build:  gfortran -std=f2008 -c rodkit.f90   (or use the installed
!         rodkit.mod and librodkit_fortran.a: pkg-config rodkit-fortran, or
!         CMake's rodkit::fortran), then `use rodkit` and link -lrodkit.
!
! Conventions (all functions, as in the header):
!  - Fallible functions return integer(c_int32_t): 0 success, > 0 success
!    with information, < 0 failure (RODKIT_STATUS_*). `if (st < 0)` catches
!    every failure.
!  - After a failure, rodkit_last_error() (module procedure below) returns a
!    message naming the offending argument and value (thread-local).
!  - Matrices are column-major with an explicit leading dimension, i.e. plain
!    Fortran arrays: pass k(ldk, 3) as `k` and `ldk`. Arrays are owned by the
!    caller and borrowed for the duration of the call only; rodkit keeps no
!    pointer to them. Counts and sizes are integer(c_int64_t).
!  - Handles (rod, branch, tube, run) are type(c_ptr); free each with its
!    rodkit_*_free.
!  - Every function is reentrant and thread-safe on distinct arguments;
!    rodkit starts no threads unless asked per call or per handle.
!  - Character arguments are C strings: NUL-terminated arrays of
!    character(kind=c_char) (append c_null_char). Returned type(c_ptr)
!    strings are owned by rodkit (never deallocate them); convert them with
!    the module procedures rodkit_status_message and rodkit_last_error.
!  - Callbacks (type(c_funptr), from c_funloc of a bind(c) procedure with
!    the abstract interface below) must not unwind through rodkit.
!
";

impl Gen {
    fn versions(&mut self, out: &mut String, v: &Versions) {
        self.kinds.insert("c_int32_t");
        out.push_str(&rule(
            "Library version (from Cargo.toml) and ABI version (from src/version.rs) of the header this \
             module was generated with. Compare them with rodkit_version() and rodkit_library_abi_version() \
             at run time to detect a module/library mismatch.",
        ));
        for (name, value) in [("MAJOR", &v.major), ("MINOR", &v.minor), ("PATCH", &v.patch)] {
            writeln!(out, "    integer(c_int32_t), parameter :: RODKIT_VERSION_{name} = {value}").unwrap();
        }
        writeln!(out, "    character(len=*), parameter :: RODKIT_VERSION_STRING = \"{}\"", v.string).unwrap();
        writeln!(out, "    integer(c_int32_t), parameter :: RODKIT_ABI_VERSION = {}\n", v.abi).unwrap();
    }

    fn enumeration(&mut self, out: &mut String, e: &Enum) -> Result<(), String> {
        match e.repr.ty {
            Some(r) if r.signed && r.kind == IntKind::B32 => {}
            _ => return Err(format!("enum {}: only #[repr(i32)] enums are mapped", e.export_name)),
        }
        self.kinds.insert("c_int32_t");
        let mut head = format!("enum {}", e.export_name);
        if let Some(first) = first_sentence(&e.documentation) {
            head = format!("{head}: {first}");
        }
        out.push_str(&rule(&head));
        for variant in &e.variants {
            if !matches!(variant.body, cbindgen::ir::VariantBody::Empty(_)) {
                return Err(format!("enum {}: variant {} carries data", e.export_name, variant.export_name));
            }
            let value = variant.discriminant.as_ref().map(literal).transpose()?.ok_or_else(|| {
                format!("enum {}: variant {} needs an explicit value", e.export_name, variant.export_name)
            })?;
            doc(out, &variant.documentation, 4);
            writeln!(out, "    integer(c_int32_t), parameter :: {} = {value}", variant.export_name).unwrap();
        }
        out.push('\n');
        Ok(())
    }

    fn structure(&mut self, out: &mut String, s: &Struct) -> Result<(), String> {
        let name = fortran_name(&s.export_name);
        let mut head = format!("{} (type {name})", s.export_name);
        if let Some(first) = first_sentence(&s.documentation) {
            head = format!("{head}: {first}");
        }
        out.push_str(&rule(&head));
        doc(out, &s.documentation, 4);
        writeln!(out, "    type, bind(c) :: {name}").unwrap();
        let mut seen = HashSet::new();
        for field in &s.fields {
            if !seen.insert(field.name.to_ascii_lowercase()) {
                return Err(format!(
                    "struct {}: field {} differs from another only in case",
                    s.export_name, field.name
                ));
            }
            let (ty, dims) = match &field.ty {
                Type::Array(inner, len) => {
                    let len = match len {
                        ConstExpr::Value(v) => v.clone(),
                        ConstExpr::Path(p) => {
                            return Err(format!("field {}: array length {}", field.name, p.export_name()))
                        }
                    };
                    (self.value_type(inner)?, format!("({len})"))
                }
                Type::Ptr { .. } => {
                    self.kinds.insert("c_ptr");
                    ("type(c_ptr)".to_string(), String::new())
                }
                Type::FuncPtr { .. } => {
                    self.kinds.insert("c_funptr");
                    ("type(c_funptr)".to_string(), String::new())
                }
                ty => (self.value_type(ty).map_err(|e| format!("struct {}: {e}", s.export_name))?, String::new()),
            };
            doc(out, &field.documentation, 8);
            writeln!(out, "        {ty} :: {}{dims}", field.name).unwrap();
        }
        writeln!(out, "    end type {name}\n").unwrap();
        Ok(())
    }

    /// A number, an enum, a struct or a callback held by value.
    fn value_type(&mut self, ty: &Type) -> Result<String, String> {
        Ok(match ty {
            Type::Primitive(p) => {
                let (decl, kind) = primitive(p)?;
                self.kinds.insert(kind);
                decl.to_string()
            }
            Type::Path(p) => match self.names.get(p.export_name()) {
                Some(Named::Enum) => {
                    self.kinds.insert("c_int32_t");
                    "integer(c_int32_t)".to_string()
                }
                Some(Named::Struct) => format!("type({})", fortran_name(p.export_name())),
                Some(Named::Callback) => {
                    self.kinds.insert("c_funptr");
                    "type(c_funptr)".to_string()
                }
                Some(Named::Opaque) => return Err(format!("opaque {} held by value", p.export_name())),
                None => return Err(format!("unknown type {}", p.export_name())),
            },
            other => return Err(format!("type {other:?} has no Fortran value mapping")),
        })
    }

    fn function(&mut self, out: &mut String, f: &Function) -> Result<(), String> {
        let arrays = f.annotations.list("fortran-arrays").unwrap_or_default();
        let args: Vec<(String, Type)> = f
            .args
            .iter()
            .map(|a| a.name.clone().map(|n| (n, a.ty.clone())).ok_or("an unnamed argument"))
            .collect::<Result<_, _>>()?;
        for a in &arrays {
            if !args.iter().any(|(n, _)| n == a) {
                return Err(format!("cbindgen:fortran-arrays names `{a}`, which is not an argument"));
            }
        }
        let result = f.annotations.atom("fortran-result").flatten();
        out.push('\n');
        doc(out, &f.documentation, 8);
        self.procedure(out, f.path.name(), Some(f.path.name()), &f.ret, &args, &arrays, result)
    }

    /// One interface body: a function (or subroutine for void) with BIND(C).
    #[allow(clippy::too_many_arguments)]
    fn procedure(
        &mut self,
        out: &mut String,
        name: &str,
        c_name: Option<&str>,
        ret: &Type,
        args: &[(String, Type)],
        arrays: &[String],
        result: Option<String>,
    ) -> Result<(), String> {
        let mut imports = BTreeSet::new();
        let mut types = BTreeSet::new();
        let mut decls = Vec::new();
        let mut seen = HashSet::new();
        for (arg, ty) in args {
            if !seen.insert(arg.to_ascii_lowercase()) {
                return Err(format!("argument {arg} differs from another only in case"));
            }
            let array = arrays.iter().any(|a| a == arg);
            let (decl, kind, ty_name) = self.dummy(arg, ty, array)?;
            imports.extend(kind);
            types.extend(ty_name);
            decls.push(decl);
        }
        let is_function = !matches!(ret, Type::Primitive(PrimitiveType::Void));
        let mut result_decl = None;
        let mut result_name = String::new();
        if is_function {
            let (decl, kind, default) = match ret {
                Type::Primitive(p) => {
                    let (decl, kind) = primitive(p)?;
                    (decl.to_string(), kind, "status")
                }
                Type::Ptr { .. } => ("type(c_ptr)".to_string(), "c_ptr", "message"),
                other => return Err(format!("return type {other:?} has no Fortran mapping")),
            };
            result_name = result.unwrap_or_else(|| default.to_string());
            if seen.contains(&result_name.to_ascii_lowercase()) {
                result_name.push_str("_result");
            }
            self.kinds.insert(kind);
            imports.insert(kind);
            result_decl = Some(format!("{decl} :: {result_name}"));
        }
        let names: Vec<&str> = args.iter().map(|(n, _)| n.as_str()).collect();
        let keyword = if is_function { "function" } else { "subroutine" };
        let bind = match c_name {
            Some(c) => format!("bind(c, name=\"{c}\")"),
            None => "bind(c)".to_string(),
        };
        let tail = if is_function { format!(" result({result_name}) {bind}") } else { format!(" {bind}") };
        let head = format!("        {keyword} {name}({}){tail}", names.join(", "));
        if head.len() <= WIDTH {
            writeln!(out, "{head}").unwrap();
        } else {
            let open = format!("        {keyword} {name}(");
            let list = wrap_inline(&open, &names, "                ");
            writeln!(out, "{list}) &\n                {}", tail.trim_start()).unwrap();
        }
        let mut import: Vec<&str> = imports.into_iter().collect();
        let type_names: Vec<String> = types.into_iter().collect();
        import.extend(type_names.iter().map(String::as_str));
        if !import.is_empty() {
            out.push_str(&wrap("            import :: ", &import, "                "));
        }
        for d in decls {
            writeln!(out, "            {d}").unwrap();
        }
        if let Some(r) = result_decl {
            writeln!(out, "            {r}").unwrap();
        }
        writeln!(out, "        end {keyword} {name}").unwrap();
        Ok(())
    }

    /// The declaration of one dummy argument, the iso_c_binding name it
    /// uses and the derived type it uses.
    fn dummy(
        &mut self,
        arg: &str,
        ty: &Type,
        array: bool,
    ) -> Result<(String, Option<&'static str>, Option<String>), String> {
        let by_value = |s: &mut Self, ty: &Type| -> Result<_, String> {
            let decl = s.value_type(ty)?;
            Ok(split(decl))
        };
        let (decl, kind, tname) = match ty {
            Type::Primitive(_) | Type::Path(_) => {
                if array {
                    return Err(format!("`{arg}` is passed by value, not an array"));
                }
                let (decl, kind, tname) = by_value(self, ty)?;
                (format!("{decl}, value :: {arg}"), kind, tname)
            }
            Type::FuncPtr { .. } => {
                self.kinds.insert("c_funptr");
                (format!("type(c_funptr), value :: {arg}"), Some("c_funptr"), None)
            }
            Type::Ptr { ty: inner, is_const, .. } => {
                let opaque =
                    matches!(&**inner, Type::Path(p) if self.names.get(p.export_name()) == Some(&Named::Opaque));
                match &**inner {
                    Type::Primitive(PrimitiveType::Void) => {
                        self.kinds.insert("c_ptr");
                        (format!("type(c_ptr), value :: {arg}"), Some("c_ptr"), None)
                    }
                    _ if opaque => {
                        self.kinds.insert("c_ptr");
                        (format!("type(c_ptr), value :: {arg}"), Some("c_ptr"), None)
                    }
                    Type::Ptr { .. } => {
                        self.kinds.insert("c_ptr");
                        (format!("type(c_ptr), intent(out) :: {arg}"), Some("c_ptr"), None)
                    }
                    Type::Primitive(PrimitiveType::Char) => {
                        self.kinds.insert("c_char");
                        let intent = if *is_const { "in" } else { "out" };
                        (format!("character(kind=c_char), intent({intent}) :: {arg}(*)"), Some("c_char"), None)
                    }
                    Type::Primitive(_) | Type::Path(_) => {
                        let (decl, kind, tname) = by_value(self, inner)?;
                        if matches!(&**inner, Type::Path(p) if self.names.get(p.export_name()) == Some(&Named::Callback))
                        {
                            return Err(format!("`{arg}`: pointer to a callback"));
                        }
                        let intent = match (*is_const, array) {
                            (true, _) => "in",
                            (false, true) => "inout",
                            (false, false) => "out",
                        };
                        let dims = if array { "(*)" } else { "" };
                        (format!("{decl}, intent({intent}) :: {arg}{dims}"), kind, tname)
                    }
                    other => return Err(format!("`{arg}`: pointer to {other:?} has no Fortran mapping")),
                }
            }
            Type::Array(..) => return Err(format!("`{arg}`: C array parameter")),
        };
        if array && !decl.ends_with("(*)") {
            return Err(format!("cbindgen:fortran-arrays lists `{arg}`, which is not a pointer to numbers or structs"));
        }
        Ok((decl, kind, tname))
    }
}

/// `real(c_double)` → its kind for `import`; `type(x)` → the type's name.
fn split(decl: String) -> (String, Option<&'static str>, Option<String>) {
    for kind in [
        "c_double",
        "c_float",
        "c_int32_t",
        "c_int64_t",
        "c_int8_t",
        "c_int16_t",
        "c_int",
        "c_size_t",
        "c_bool",
        "c_char",
        "c_funptr",
    ] {
        if decl.ends_with(&format!("({kind})")) {
            return (decl, Some(kind), None);
        }
    }
    let tname = decl.strip_prefix("type(").and_then(|d| d.strip_suffix(')')).map(str::to_string);
    (decl, None, tname)
}

fn primitive(p: &PrimitiveType) -> Result<(&'static str, &'static str), String> {
    Ok(match p {
        PrimitiveType::Double => ("real(c_double)", "c_double"),
        PrimitiveType::Float => ("real(c_float)", "c_float"),
        PrimitiveType::Bool => ("logical(c_bool)", "c_bool"),
        PrimitiveType::Char => ("character(kind=c_char)", "c_char"),
        PrimitiveType::Integer { signed: true, kind, .. } => match kind {
            IntKind::B8 => ("integer(c_int8_t)", "c_int8_t"),
            IntKind::B16 => ("integer(c_int16_t)", "c_int16_t"),
            IntKind::B32 => ("integer(c_int32_t)", "c_int32_t"),
            IntKind::B64 => ("integer(c_int64_t)", "c_int64_t"),
            IntKind::Int => ("integer(c_int)", "c_int"),
            other => return Err(format!("integer kind {other:?} has no fixed Fortran kind")),
        },
        PrimitiveType::Integer { signed: false, .. } => {
            return Err("unsigned integer: Fortran has none (c-api.md: int64_t counts)".to_string())
        }
        other => return Err(format!("{other:?} has no Fortran mapping")),
    })
}

fn literal(l: &Literal) -> Result<String, String> {
    match l {
        Literal::Expr(e) => Ok(e.clone()),
        Literal::PostfixUnaryOp { op, value } => Ok(format!("{op}{}", literal(value)?)),
        other => Err(format!("enum value {other:?} is not a plain integer")),
    }
}

/// `RodkitRodSpec` → `rodkit_rod_spec`.
fn fortran_name(c: &str) -> String {
    let mut s = String::new();
    let mut prev_lower = false;
    for ch in c.chars() {
        if ch.is_ascii_uppercase() && prev_lower {
            s.push('_');
        }
        prev_lower = ch.is_ascii_lowercase() || ch.is_ascii_digit();
        s.push(ch.to_ascii_lowercase());
    }
    s
}

fn doc_lines(d: &Documentation) -> Vec<String> {
    d.doc_comment.iter().map(|l| l.strip_prefix(' ').unwrap_or(l).trim_end().to_string()).collect()
}

fn first_sentence(d: &Documentation) -> Option<String> {
    let text = doc_lines(d).into_iter().take_while(|l| !l.is_empty()).collect::<Vec<_>>().join(" ");
    let end = text.find(". ").map(|i| i + 1).unwrap_or(text.len());
    let s = text[..end].trim();
    (!s.is_empty() && s.len() <= 200).then(|| s.to_string())
}

/// The C documentation as Fortran comments.
fn doc(out: &mut String, d: &Documentation, indent: usize) {
    for line in doc_lines(d) {
        if line.is_empty() {
            writeln!(out, "{:indent$}!", "").unwrap();
        } else {
            writeln!(out, "{:indent$}! {line}", "").unwrap();
        }
    }
}

/// A section rule with a wrapped title.
fn rule(title: &str) -> String {
    let mut out = String::from("    ! -------------------------------------------------------------------------\n");
    let mut line = String::from("    !");
    for word in title.split_whitespace() {
        if line.len() + 1 + word.len() > 80 {
            out.push_str(&line);
            out.push('\n');
            line = String::from("    !");
        }
        line.push(' ');
        line.push_str(word);
    }
    out.push_str(&line);
    out.push('\n');
    out.push_str("    ! -------------------------------------------------------------------------\n");
    out
}

/// `head item, item, …` with continuation lines, ending in a newline.
fn wrap(head: &str, items: &[&str], cont: &str) -> String {
    let mut out = wrap_inline(head, items, cont);
    out.push('\n');
    out
}

fn wrap_inline(head: &str, items: &[&str], cont: &str) -> String {
    let mut out = String::new();
    let mut line = head.to_string();
    let mut empty = true;
    for (i, item) in items.iter().enumerate() {
        let sep = if i + 1 < items.len() { ", " } else { "" };
        if !empty && line.len() + item.len() + sep.len() > WIDTH {
            out.push_str(line.trim_end());
            out.push_str(" &\n");
            line = cont.to_string();
        }
        line.push_str(item);
        line.push_str(sep);
        empty = false;
    }
    out.push_str(&line);
    out
}
