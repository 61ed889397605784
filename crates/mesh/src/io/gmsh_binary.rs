//! Binary Gmsh `.msh` files (4.1 and 2.2, either byte order), turned into the ASCII text of the
//! same file so that one parser, with all its checks, reads both.
//!
//! A binary file keeps ASCII lines around its binary data: `$MeshFormat` gives `file-type` 1,
//! the `data-size` (4.1: the bytes of a `size_t`; 2.2: of a double) and then the binary int 1
//! that tells the byte order. `$PhysicalNames`, `$Comments` and the string, real and integer
//! tags of a `$NodeData` view stay ASCII. The binary layouts (the Gmsh reference manual, "MSH
//! file format"; `size_t` is `data-size` bytes, `int` 4, `double` 8):
//!
//! * 4.1 `$Entities`: four `size_t` counts; a point is `int` tag, three doubles, `size_t`
//!   number of physical tags and their `int`s; a curve, surface or volume the same with six
//!   doubles (its bounding box), then `size_t` number of bounding entities and their `int`s.
//! * 4.1 `$Nodes`: four `size_t` (blocks, nodes, smallest and largest tag); per block `int`
//!   dimension, `int` entity, `int` parametric flag, `size_t` count, the count's `size_t` tags,
//!   then per node three doubles (and the entity's dimension more with the flag set).
//! * 4.1 `$Elements`: four `size_t`; per block `int` dimension, entity and element type,
//!   `size_t` count, then per element a `size_t` tag and the type's number of `size_t` nodes.
//! * 2.2 `$Nodes`: an ASCII count line, then per node an `int` tag and three doubles.
//! * 2.2 `$Elements`: an ASCII count line, then blocks of `int` type, `int` count and `int`
//!   number of tags, each followed by that many elements of `int` number, the tags and the
//!   type's nodes, all `int`.
//! * `$NodeData` (both): after the ASCII tags, per value an `int` node tag and as many doubles
//!   as the view has components.
//!
//! Other sections, which the reader skips, are copied where they are text and left empty where
//! they are not; their end is found by their `$End` line.
use super::gmsh::element_type;
use super::{file_err, push_float};
use crate::MeshError;
use std::path::Path;

/// The ASCII text of a binary file, and where in the file each of its lines came from.
pub(super) struct Ascii {
    pub(super) text: String,
    /// From line `runs[i].0` (0-based) on, line `l` came from byte `runs[i].1 + (l - runs[i].0)
    /// * runs[i].2`: a block of records of one size is one run.
    runs: Vec<(usize, usize, usize)>,
    lines: usize,
    len: usize,
}

impl Ascii {
    /// The byte of the file that line `line` (1-based) of the text came from.
    fn byte_of_line(&self, line: usize) -> usize {
        if line == 0 || line > self.lines {
            return self.len;
        }
        let l = line - 1;
        let k = self.runs.partition_point(|r| r.0 <= l);
        match k.checked_sub(1).map(|k| self.runs[k]) {
            Some((first, at, stride)) => at + (l - first) * stride,
            None => 0,
        }
    }

    /// `e`, an error of the ASCII parser on the text, with the line it names made the byte of
    /// the file that line came from: a binary file has no lines of its own to count.
    pub(super) fn locate(&self, e: MeshError) -> MeshError {
        match e {
            MeshError::File { path, message } => {
                let line = message
                    .strip_prefix("line ")
                    .and_then(|m| m.split_once(": "))
                    .and_then(|(n, rest)| Some((n.parse::<usize>().ok()?, rest)));
                let message = match line {
                    Some((n, rest)) => format!("byte {}: {rest}", self.byte_of_line(n)),
                    None => message,
                };
                MeshError::File { path, message }
            }
            e => e,
        }
    }
}

/// The text of `bytes` as an ASCII `.msh` file when they are a binary one (`file-type` 1);
/// `None` for any other file, which the ASCII parser reads (or refuses) as it is.
pub(super) fn ascii_of_binary(bytes: &[u8], path: &Path) -> Result<Option<Ascii>, MeshError> {
    let mut r = Reader {
        b: bytes,
        pos: 0,
        big: false,
        size_t: 8,
        section: "$MeshFormat",
    };
    if r.token() != Some(&b"$MeshFormat"[..]) {
        return Ok(None);
    }
    let (Some(version), Some(b"1")) = (r.token(), r.token()) else {
        return Ok(None);
    };
    let version = String::from_utf8_lossy(version).into_owned();
    let mut out = Out::default();
    convert(&mut r, &version, &mut out).map_err(|m| file_err(path, m))?;
    Ok(Some(Ascii {
        text: out.text,
        runs: out.runs,
        lines: out.lines,
        len: bytes.len(),
    }))
}

/// Sections that are binary in a binary file but that the reader skips: left empty.
const SKIPPED: &[&str] = &[
    "$Periodic",
    "$GhostElements",
    "$ElementData",
    "$ElementNodeData",
    "$PartitionedEntities",
    "$Parametrizations",
    "$ParametricNodes",
];

fn convert(r: &mut Reader, version: &str, out: &mut Out) -> Result<(), String> {
    let data_size = r.token();
    let v2 = match version {
        "4.1" => false,
        "2.2" | "2.1" | "2.0" | "2" => true,
        _ => {
            // The parser names the version it does not read.
            out.at(0, 0);
            out.line(&format!("$MeshFormat\n{version} 0 8\n$EndMeshFormat"));
            return Ok(());
        }
    };
    let data_size = data_size
        .and_then(|d| std::str::from_utf8(d).ok()?.parse::<usize>().ok())
        .ok_or_else(|| r.err("expected the data size after the file type"))?;
    match (v2, data_size) {
        (false, 4 | 8) | (true, 8) => r.size_t = data_size,
        _ => {
            return Err(r.err(format!(
                "binary data size {data_size} is not supported: {}",
                if v2 {
                    "2.2's is the size of a double, 8"
                } else {
                    "4.1's is the size of a size_t, 8 (or 4)"
                }
            )))
        }
    }
    r.rest_of_line();
    let at = r.pos;
    let one = r.take(4, "the byte-order int")?;
    r.big = match one {
        [1, 0, 0, 0] => false,
        [0, 0, 0, 1] => true,
        _ => {
            return Err(format!(
                "byte {at}: the binary int after the format line is {one:02x?}, not 1 in either \
                 byte order"
            ))
        }
    };
    out.at(0, 0);
    out.line(&format!("$MeshFormat\n{version} 0 {data_size}"));
    end_section(r, out)?;
    loop {
        r.skip_space();
        if r.pos == r.b.len() {
            return Ok(());
        }
        let start = r.pos;
        let name = String::from_utf8_lossy(r.rest_of_line()).trim().to_string();
        if !name.starts_with('$') || name.starts_with("$End") {
            return Err(format!(
                "byte {start}: expected a section such as $Nodes, found '{}'",
                name.chars().take(40).collect::<String>()
            ));
        }
        out.at(start, 0);
        out.line(&name);
        r.section = match name.as_str() {
            "$Entities" if !v2 => "$Entities",
            "$Nodes" => "$Nodes",
            "$Elements" => "$Elements",
            "$NodeData" => "$NodeData",
            _ => {
                other_section(r, &name, out)?;
                continue;
            }
        };
        match r.section {
            "$Entities" => entities(r, out)?,
            "$Nodes" if v2 => nodes_v2(r, out)?,
            "$Nodes" => nodes_v4(r, out)?,
            "$Elements" if v2 => elements_v2(r, out)?,
            "$Elements" => elements_v4(r, out)?,
            _ => {
                if !node_data(r, out)? {
                    let end = find_end(r, &name)?;
                    r.pos = end;
                }
            }
        }
        end_section(r, out)?;
    }
}

/// Skip a section the reader does not convert: an ASCII one (its text valid UTF-8) is copied
/// for the parser to read or skip; a binary one is left empty.
fn other_section(r: &mut Reader, name: &str, out: &mut Out) -> Result<(), String> {
    let end = find_end(r, name)?;
    let body = &r.b[r.pos..end];
    match std::str::from_utf8(body) {
        Ok(text) if !SKIPPED.contains(&name) => {
            let mut at = r.pos;
            for line in text.split_inclusive('\n') {
                out.at(at, 0);
                out.line(line.trim_end_matches(['\n', '\r']));
                at += line.len();
            }
        }
        _ => {}
    }
    r.pos = end;
    r.rest_of_line();
    out.at(end, 0);
    out.line(&format!("$End{}", &name[1..]));
    Ok(())
}

/// Where the line `$End<name>` of section `name` starts.
fn find_end(r: &Reader, name: &str) -> Result<usize, String> {
    let end = format!("$End{}", &name[1..]);
    let end = end.as_bytes();
    let mut from = r.pos;
    while let Some(k) = r.b[from..].windows(end.len()).position(|w| w == end) {
        let at = from + k;
        let line_start = at == r.pos || r.b[at - 1] == b'\n';
        let after = r.b.get(at + end.len());
        if line_start && after.is_none_or(u8::is_ascii_whitespace) {
            return Ok(at);
        }
        from = at + 1;
    }
    Err(format!(
        "byte {}: section {name} has no $End{}",
        r.pos,
        &name[1..]
    ))
}

/// The `$End` line of the current section, after its data.
fn end_section(r: &mut Reader, out: &mut Out) -> Result<(), String> {
    r.skip_space();
    let at = r.pos;
    let end = format!("$End{}", &r.section[1..]);
    match r.token() {
        Some(t) if t == end.as_bytes() => {
            r.rest_of_line();
            out.at(at, 0);
            out.line(&end);
            Ok(())
        }
        found => Err(format!(
            "byte {at}: expected {end} after the binary data of {}, found {}; the file is \
             corrupt, or its counts are not those of its data",
            r.section,
            match found {
                Some(t) => format!("'{}'", String::from_utf8_lossy(&t[..t.len().min(40)])),
                None => "the end of the file".to_string(),
            }
        )),
    }
}

fn entities(r: &mut Reader, out: &mut Out) -> Result<(), String> {
    out.at(r.pos, 0);
    let mut counts = [0; 4];
    for c in &mut counts {
        *c = r.size("the number of entities")?;
        out.uint(*c);
    }
    out.end();
    for (dim, &count) in counts.iter().enumerate() {
        let coords = if dim == 0 { 3 } else { 6 };
        let bounded = usize::from(dim > 0);
        r.fits(count, 4 + 8 * coords + r.size_t * (1 + bounded), "entities")?;
        for _ in 0..count {
            out.at(r.pos, 0);
            out.int(r.int("an entity tag")?);
            for _ in 0..coords {
                out.float(r.double("an entity's coordinates")?);
            }
            for _ in 0..1 + bounded {
                let n = r.size("a number of physical or bounding tags")?;
                r.fits(n, 4, "physical or bounding tags")?;
                out.uint(n);
                for _ in 0..n {
                    out.int(r.int("a physical or bounding tag")?);
                }
            }
            out.end();
        }
    }
    Ok(())
}

/// A 4.1 section's first line, four size_t: its blocks, its count, its smallest and largest
/// tags (`what` names each); the number of blocks.
fn section_counts(r: &mut Reader, out: &mut Out, what: [&str; 4]) -> Result<u64, String> {
    out.at(r.pos, 0);
    let blocks = r.size(what[0])?;
    out.uint(blocks);
    for w in &what[1..] {
        out.uint(r.size(w)?);
    }
    out.end();
    Ok(blocks)
}

fn nodes_v4(r: &mut Reader, out: &mut Out) -> Result<(), String> {
    let blocks = section_counts(
        r,
        out,
        [
            "the number of node blocks",
            "the number of nodes",
            "the smallest node tag",
            "the largest",
        ],
    )?;
    r.fits(blocks, 12 + r.size_t, "node blocks")?;
    for _ in 0..blocks {
        out.at(r.pos, 0);
        let dim = r.int("a node block's entity dimension")?;
        let entity = r.int("a node block's entity tag")?;
        let at = r.pos;
        let parametric = r.int("a node block's parametric flag")?;
        let n = r.size("the number of nodes in a block")?;
        for v in [dim, entity, parametric] {
            out.int(v);
        }
        out.uint(n);
        out.end();
        let extra = match (parametric, dim) {
            (0, _) => 0,
            (1, 0..=3) => dim as usize,
            _ => {
                return Err(format!(
                    "byte {at}: a node block of dimension {dim} has the parametric flag \
                     {parametric}; it must be 0 or 1, on an entity of dimension 0 to 3"
                ))
            }
        };
        let record = 8 * (3 + extra);
        r.fits(n, r.size_t + record, "nodes")?;
        out.at(r.pos, r.size_t);
        for _ in 0..n {
            out.uint(r.size("a node tag")?);
            out.end();
        }
        out.at(r.pos, record);
        for _ in 0..n {
            for _ in 0..3 + extra {
                out.float(r.double("a node's coordinates")?);
            }
            out.end();
        }
    }
    Ok(())
}

/// The number of nodes of an element type; an error naming a type the reader does not know.
fn nodes_of(etype: i32, at: usize) -> Result<usize, String> {
    element_type(i64::from(etype))
        .map(|(n, _)| n)
        .ok_or_else(|| format!("byte {at}: element type {etype} is not supported"))
}

fn elements_v4(r: &mut Reader, out: &mut Out) -> Result<(), String> {
    let blocks = section_counts(
        r,
        out,
        [
            "the number of element blocks",
            "the number of elements",
            "the smallest element tag",
            "the largest",
        ],
    )?;
    r.fits(blocks, 12 + r.size_t, "element blocks")?;
    for _ in 0..blocks {
        out.at(r.pos, 0);
        for what in ["an element block's entity dimension", "its entity tag"] {
            out.int(r.int(what)?);
        }
        let at = r.pos;
        let etype = r.int("an element type")?;
        let n = r.size("the number of elements in a block")?;
        out.int(etype);
        out.uint(n);
        out.end();
        let record = r.size_t * (1 + nodes_of(etype, at)?);
        r.fits(n, record, "elements")?;
        out.at(r.pos, record);
        for _ in 0..n {
            for _ in 0..record / r.size_t {
                out.uint(r.size("an element's tag or nodes")?);
            }
            out.end();
        }
    }
    Ok(())
}

/// A count on an ASCII line of its own before binary data: the line, then the data.
fn ascii_count(r: &mut Reader, what: &str, out: &mut Out) -> Result<u64, String> {
    r.skip_space();
    out.at(r.pos, 0);
    let n = r.ascii_uint(what)?;
    r.rest_of_line();
    out.uint(n);
    out.end();
    Ok(n)
}

fn nodes_v2(r: &mut Reader, out: &mut Out) -> Result<(), String> {
    let n = ascii_count(r, "the number of nodes", out)?;
    r.fits(n, 4 + 24, "nodes")?;
    out.at(r.pos, 28);
    for _ in 0..n {
        out.int(r.int("a node tag")?);
        for _ in 0..3 {
            out.float(r.double("a node's coordinates")?);
        }
        out.end();
    }
    Ok(())
}

fn elements_v2(r: &mut Reader, out: &mut Out) -> Result<(), String> {
    let total = ascii_count(r, "the number of elements", out)?;
    r.fits(total, 4, "elements")?;
    let mut left = total;
    while left > 0 {
        let at = r.pos;
        let etype = r.int("an element block's type")?;
        let n = r.int("the number of elements in a block")?;
        let tags = r.int("the number of tags of a block's elements")?;
        let (Ok(n), Ok(tags)) = (u64::try_from(n), usize::try_from(tags)) else {
            return Err(format!(
                "byte {at}: a block of {n} elements of {tags} tags each"
            ));
        };
        if n > left {
            return Err(format!(
                "byte {at}: a block of {n} elements, past the {total} the section gives"
            ));
        }
        let record = tags
            .checked_add(1 + nodes_of(etype, at)?)
            .and_then(|k| k.checked_mul(4))
            .ok_or_else(|| format!("byte {at}: elements of {tags} tags each"))?;
        r.fits(n, record, "elements")?;
        out.at(r.pos, record);
        for _ in 0..n {
            // 2.2's ASCII line: number, type, number of tags, tags, nodes.
            out.int(r.int("an element number")?);
            out.int(etype);
            out.uint(tags as u64);
            for _ in 1..record / 4 {
                out.int(r.int("an element's tags or nodes")?);
            }
            out.end();
        }
        left -= n;
    }
    Ok(())
}

/// A `$NodeData` view: its ASCII tags copied, its values converted. False where the integer
/// tags give no layout (fewer than three, or negative): the values are then skipped, and the
/// parser, if it reads the view, names the fault.
fn node_data(r: &mut Reader, out: &mut Out) -> Result<bool, String> {
    let strings = ascii_count(r, "the number of string tags", out)?;
    for _ in 0..strings {
        if r.pos == r.b.len() {
            return Err(r.err("the file ends in $NodeData's string tags"));
        }
        out.at(r.pos, 0);
        out.line(String::from_utf8_lossy(r.rest_of_line()).trim());
    }
    let reals = ascii_count(r, "the number of real tags", out)?;
    for _ in 0..reals {
        r.skip_space();
        out.at(r.pos, 0);
        let t = r.token().ok_or_else(|| r.err("expected a real tag"))?;
        out.line(&String::from_utf8_lossy(t));
    }
    let ints = ascii_count(r, "the number of integer tags", out)?;
    let mut tags = Vec::new();
    for _ in 0..ints {
        r.skip_space();
        out.at(r.pos, 0);
        let t = r.token().ok_or_else(|| r.err("expected an integer tag"))?;
        let t = String::from_utf8_lossy(t);
        if tags.len() < 3 {
            tags.push(t.parse::<i64>().ok());
        }
        out.line(&t);
    }
    r.rest_of_line();
    let (Some(Some(components)), Some(Some(count))) = (tags.get(1), tags.get(2)) else {
        return Ok(false);
    };
    let (Ok(components), Ok(count)) = (usize::try_from(*components), u64::try_from(*count)) else {
        return Ok(false);
    };
    let record = components
        .checked_mul(8)
        .and_then(|b| b.checked_add(4))
        .ok_or_else(|| r.err(format!("$NodeData has {components} components")))?;
    r.fits(count, record, "values")?;
    out.at(r.pos, record);
    for _ in 0..count {
        out.int(r.int("a node tag")?);
        for _ in 0..components {
            out.float(r.double("a node value")?);
        }
        out.end();
    }
    Ok(true)
}

/// The bytes of a binary file, read from `pos` on in its byte order.
struct Reader<'a> {
    b: &'a [u8],
    pos: usize,
    big: bool,
    /// Bytes of a `size_t` (4.1's counts and tags).
    size_t: usize,
    /// The section being read, for errors.
    section: &'static str,
}

impl<'a> Reader<'a> {
    fn err(&self, message: impl std::fmt::Display) -> String {
        format!("byte {}: {message}", self.pos)
    }

    /// The next `n` bytes.
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], String> {
        let left = self.b.len() - self.pos;
        if n > left {
            return Err(self.err(format!(
                "the file ends in {}, in {what} ({n} bytes, {left} left)",
                self.section
            )));
        }
        self.pos += n;
        Ok(&self.b[self.pos - n..self.pos])
    }

    fn uint(&mut self, n: usize, what: &str) -> Result<u64, String> {
        let bytes = self.take(n, what)?;
        let fold = |u: u64, &x: &u8| (u << 8) | u64::from(x);
        Ok(if self.big {
            bytes.iter().fold(0, fold)
        } else {
            bytes.iter().rev().fold(0, fold)
        })
    }

    /// A `size_t`.
    fn size(&mut self, what: &str) -> Result<u64, String> {
        self.uint(self.size_t, what)
    }

    fn int(&mut self, what: &str) -> Result<i32, String> {
        Ok(self.uint(4, what)? as u32 as i32)
    }

    fn double(&mut self, what: &str) -> Result<f64, String> {
        Ok(f64::from_bits(self.uint(8, what)?))
    }

    /// That `count` records of at least `each` bytes fit in what is left of the file: a
    /// count is checked before anything is read (or made) for it.
    fn fits(&self, count: u64, each: usize, what: &str) -> Result<(), String> {
        let left = (self.b.len() - self.pos) as u64;
        match count.checked_mul(each as u64) {
            Some(need) if need <= left => Ok(()),
            _ => Err(self.err(format!(
                "{} gives {count} {what} of {each} bytes or more, but {left} bytes are left: the \
                 file is cut short, or the count is corrupt",
                self.section
            ))),
        }
    }

    fn skip_space(&mut self) {
        while self.b.get(self.pos).is_some_and(u8::is_ascii_whitespace) {
            self.pos += 1;
        }
    }

    /// The next run of non-space bytes of an ASCII line, after spaces.
    fn token(&mut self) -> Option<&'a [u8]> {
        self.skip_space();
        let start = self.pos;
        while self
            .b
            .get(self.pos)
            .is_some_and(|c| !c.is_ascii_whitespace())
        {
            self.pos += 1;
        }
        (self.pos > start).then(|| &self.b[start..self.pos])
    }

    /// An ASCII non-negative integer.
    fn ascii_uint(&mut self, what: &str) -> Result<u64, String> {
        let at = self.pos;
        let t = self.token().unwrap_or_default();
        std::str::from_utf8(t)
            .ok()
            .and_then(|t| t.parse().ok())
            .ok_or_else(|| {
                format!(
                    "byte {at}: expected {what} (a non-negative integer) in {}, found '{}'",
                    self.section,
                    String::from_utf8_lossy(&t[..t.len().min(40)])
                )
            })
    }

    /// The rest of the line (without its `\n`), and move past it: the binary data of a
    /// section starts after its ASCII lines.
    fn rest_of_line(&mut self) -> &'a [u8] {
        let start = self.pos;
        let end = self.b[start..]
            .iter()
            .position(|&c| c == b'\n')
            .map_or(self.b.len(), |k| start + k);
        self.pos = (end + 1).min(self.b.len());
        &self.b[start..end]
    }
}

/// The ASCII text being made, line by line, with where each line came from.
#[derive(Default)]
struct Out {
    text: String,
    /// Lines ended so far.
    lines: usize,
    runs: Vec<(usize, usize, usize)>,
    /// Whether the current line has a word yet.
    words: bool,
}

impl Out {
    /// The lines from here on come from `at`, `at + stride`, ...
    fn at(&mut self, at: usize, stride: usize) {
        self.runs.push((self.lines, at, stride));
    }

    fn space(&mut self) {
        if self.words {
            self.text.push(' ');
        }
        self.words = true;
    }

    fn uint(&mut self, v: u64) {
        self.space();
        self.text.push_str(itoa::Buffer::new().format(v));
    }

    fn int(&mut self, v: i32) {
        self.space();
        self.text.push_str(itoa::Buffer::new().format(v));
    }

    fn float(&mut self, v: f64) {
        self.space();
        push_float(&mut self.text, v);
    }

    fn end(&mut self) {
        self.text.push('\n');
        self.lines += 1;
        self.words = false;
    }

    /// Whole lines of text (`\n` between them).
    fn line(&mut self, s: &str) {
        for l in s.split('\n') {
            self.text.push_str(l);
            self.end();
        }
    }
}
