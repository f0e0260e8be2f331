//! A cursor over a mesh file's bytes: whitespace-separated tokens (with optional `//` and
//! `/* */` comments), numbers, and little-endian binary values, all parsed with nom. It knows
//! where it is, so every error carries `file:line` (text) or the byte offset and section
//! (binary).

// With one reader compiled in, the helpers only the other one uses are unused.
#![cfg_attr(not(all(feature = "msh", feature = "mdpa")), allow(dead_code))]

use nom::IResult;
use nom::Parser;
use nom::bytes::complete::{tag, take_till, take_till1, take_until};
use nom::character::complete::multispace1;
use nom::combinator::all_consuming;

use crate::error::{Error, ErrorKind, Location};

/// One whitespace-separated word of the file and the byte offset where it starts.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Token<'a> {
    pub(crate) text: &'a str,
    pub(crate) pos: usize,
}

/// The reading position in a file.
#[derive(Debug)]
pub(crate) struct Cursor<'a> {
    data: &'a [u8],
    pos: usize,
    file: &'a str,
    /// `//` and `/* */` comments are whitespace (mdpa).
    comments: bool,
    /// The binary section being read, if any: errors then give byte offsets.
    binary_section: Option<&'static str>,
}

fn is_ws(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | b'\n' | b'\x0b' | b'\x0c')
}

fn word(input: &[u8]) -> IResult<&[u8], &[u8]> {
    take_till1(is_ws).parse(input)
}

fn line_comment(input: &[u8]) -> IResult<&[u8], &[u8]> {
    let (input, _) = tag(&b"//"[..]).parse(input)?;
    take_till(|b| b == b'\n').parse(input)
}

fn block_comment(input: &[u8]) -> IResult<&[u8], &[u8]> {
    let (input, _) = tag(&b"/*"[..]).parse(input)?;
    let (input, body) = take_until(&b"*/"[..]).parse(input)?;
    let (input, _) = tag(&b"*/"[..]).parse(input)?;
    Ok((input, body))
}

impl<'a> Cursor<'a> {
    pub(crate) fn new(data: &'a [u8], file: &'a str, comments: bool) -> Cursor<'a> {
        Cursor {
            data,
            pos: 0,
            file,
            comments,
            binary_section: None,
        }
    }

    pub(crate) fn file(&self) -> &'a str {
        self.file
    }

    pub(crate) fn pos(&self) -> usize {
        self.pos
    }

    /// The whole file.
    pub(crate) fn data(&self) -> &'a [u8] {
        self.data
    }

    /// Moves to byte `pos` (a word boundary: the caller has read everything before it).
    pub(crate) fn set_pos(&mut self, pos: usize) {
        self.pos = pos;
    }

    /// A cursor over the same file at byte `pos`.
    pub(crate) fn at(&self, pos: usize) -> Cursor<'a> {
        Cursor {
            data: self.data,
            pos,
            file: self.file,
            comments: self.comments,
            binary_section: self.binary_section,
        }
    }

    pub(crate) fn remaining(&self) -> usize {
        self.data.len().saturating_sub(self.pos)
    }

    fn rest(&self) -> &'a [u8] {
        self.data.get(self.pos..).unwrap_or(&[])
    }

    /// Errors now give byte offsets in `section` (None: back to lines).
    pub(crate) fn set_binary(&mut self, section: Option<&'static str>) {
        self.binary_section = section;
    }

    /// The 1-based line of byte `pos`.
    pub(crate) fn line_at(&self, pos: usize) -> usize {
        let end = pos.min(self.data.len());
        1 + self.data[..end].iter().filter(|&&b| b == b'\n').count()
    }

    /// The location of byte `pos` in the current mode.
    pub(crate) fn location(&self, pos: usize) -> Location {
        match self.binary_section {
            Some(section) => Location::Byte {
                offset: pos,
                section: section.to_owned(),
            },
            None => Location::Line(self.line_at(pos)),
        }
    }

    /// An error at byte `pos`.
    pub(crate) fn error_at(&self, pos: usize, kind: ErrorKind) -> Error {
        Error::new(self.file, self.location(pos), kind)
    }

    /// An "expected …, found …" error at byte `pos`.
    pub(crate) fn expected_at(&self, pos: usize, expected: &str, found: &str) -> Error {
        self.error_at(
            pos,
            ErrorKind::Expected {
                expected: expected.to_owned(),
                found: found.to_owned(),
            },
        )
    }

    /// An "expected …, found end of file" error.
    pub(crate) fn eof(&self, expected: &str) -> Error {
        self.expected_at(self.data.len(), expected, "end of file")
    }

    /// Skips whitespace (and comments when enabled). An unterminated `/*` is an error.
    pub(crate) fn skip_ws(&mut self) -> Result<(), Error> {
        loop {
            let rest = self.rest();
            if let Ok((r, _)) = multispace1::<&[u8], nom::error::Error<&[u8]>>(rest) {
                self.pos += rest.len() - r.len();
                continue;
            }
            if self.comments {
                if let Ok((r, _)) = line_comment(rest) {
                    self.pos += rest.len() - r.len();
                    continue;
                }
                if rest.starts_with(b"/*") {
                    match block_comment(rest) {
                        Ok((r, _)) => {
                            self.pos += rest.len() - r.len();
                            continue;
                        }
                        Err(_) => {
                            return Err(self.error_at(
                                self.pos,
                                ErrorKind::Unterminated("the comment `/*`".to_owned()),
                            ));
                        }
                    }
                }
            }
            return Ok(());
        }
    }

    /// True when only whitespace (and comments) is left.
    pub(crate) fn at_end(&mut self) -> Result<bool, Error> {
        self.skip_ws()?;
        Ok(self.remaining() == 0)
    }

    /// The next word, or `None` at the end of the file. A word that is not UTF-8 is an error.
    pub(crate) fn token(&mut self) -> Result<Option<Token<'a>>, Error> {
        self.skip_ws()?;
        let rest = self.rest();
        match word(rest) {
            Ok((r, w)) => {
                let pos = self.pos;
                self.pos += rest.len() - r.len();
                let mut text = std::str::from_utf8(w)
                    .map_err(|_| self.expected_at(pos, "text", "bytes that are not UTF-8"))?;
                if self.comments {
                    // `1.0//comment`: a comment glued to a word ends it.
                    if let Some(cut) = comment_start(w)
                        && cut > 0
                    {
                        text = &text[..cut];
                        self.pos = pos + cut;
                    }
                }
                Ok(Some(Token { text, pos }))
            }
            Err(_) => Ok(None),
        }
    }

    /// The next word; the end of the file is an error that says what `expected()` returns
    /// (built only then).
    pub(crate) fn expect_token_with(
        &mut self,
        expected: impl FnOnce() -> String,
    ) -> Result<Token<'a>, Error> {
        match self.token()? {
            Some(t) => Ok(t),
            None => Err(self.eof(&expected())),
        }
    }

    /// The next word; the end of the file is an error that says `expected`.
    pub(crate) fn expect_token(&mut self, expected: &str) -> Result<Token<'a>, Error> {
        match self.token()? {
            Some(t) => Ok(t),
            None => Err(self.eof(expected)),
        }
    }

    /// The next word, which must be `word`.
    pub(crate) fn expect_word(&mut self, word: &str) -> Result<Token<'a>, Error> {
        let t = self.expect_token(&format!("`{word}`"))?;
        if t.text != word {
            return Err(self.expected_at(t.pos, &format!("`{word}`"), &format!("`{}`", t.text)));
        }
        Ok(t)
    }

    /// The rest of the current line (comments removed, trimmed), and its start offset; moves
    /// past the line end.
    pub(crate) fn rest_of_line(&mut self) -> Result<(&'a str, usize), Error> {
        let rest = self.rest();
        let start = self.pos;
        let len = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        let line = &rest[..len];
        self.pos += (len + 1).min(rest.len());
        let mut text = std::str::from_utf8(line)
            .map_err(|_| self.expected_at(start, "text", "bytes that are not UTF-8"))?;
        if self.comments
            && let Some(cut) = text.find("//")
        {
            text = &text[..cut];
        }
        Ok((text.trim(), start))
    }

    /// Moves just past the next `\n` (the end of a header line before binary data).
    pub(crate) fn skip_line_end(&mut self) -> Result<(), Error> {
        let rest = self.rest();
        match rest.iter().position(|&b| b == b'\n') {
            Some(i)
                if rest[..i]
                    .iter()
                    .all(|&b| b == b' ' || b == b'\t' || b == b'\r') =>
            {
                self.pos += i + 1;
                Ok(())
            }
            Some(_) => Err(self.expected_at(self.pos, "the end of the line", "more text")),
            None => Err(self.eof("the end of the line")),
        }
    }

    /// Moves past the next occurrence of `needle` (a line start); `None` if it never occurs.
    pub(crate) fn skip_past(&mut self, needle: &[u8]) -> Option<usize> {
        let rest = self.rest();
        let (_, before) = take_until::<_, _, nom::error::Error<&[u8]>>(needle)
            .parse(rest)
            .ok()?;
        let at = self.pos + before.len();
        self.pos = at + needle.len();
        Some(at)
    }

    // --- numbers in text ---------------------------------------------------------------

    /// The next word as an unsigned integer.
    pub(crate) fn u64(&mut self, what: &str) -> Result<u64, Error> {
        let t = self.expect_token(what)?;
        parse_u64(t.text).ok_or_else(|| self.expected_at(t.pos, what, &quote(t.text)))
    }

    /// The next word as a signed integer.
    pub(crate) fn i64(&mut self, what: &str) -> Result<i64, Error> {
        let t = self.expect_token(what)?;
        parse_i64(t.text).ok_or_else(|| self.expected_at(t.pos, what, &quote(t.text)))
    }

    /// The next word as an id that fits in 32 bits.
    pub(crate) fn id(&mut self, what: &str) -> Result<u32, Error> {
        let t = self.expect_token(what)?;
        parse_u64(t.text)
            .and_then(|v| u32::try_from(v).ok())
            .ok_or_else(|| self.expected_at(t.pos, what, &quote(t.text)))
    }

    /// The next word as a finite number.
    pub(crate) fn f64(&mut self, what: &str) -> Result<f64, Error> {
        let t = self.expect_token(what)?;
        parse_f64(t.text)
            .filter(|x| x.is_finite())
            .ok_or_else(|| self.expected_at(t.pos, what, &quote(t.text)))
    }

    // --- binary ------------------------------------------------------------------------

    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], Error> {
        let rest = self.rest();
        if rest.len() < n {
            return Err(self.eof(what));
        }
        self.pos += n;
        Ok(&rest[..n])
    }

    /// A little-endian `i32`.
    pub(crate) fn bin_i32(&mut self, what: &str) -> Result<i32, Error> {
        let b = self.take(4, what)?;
        let r: IResult<&[u8], i32> = nom::number::complete::le_i32(b);
        r.map(|(_, v)| v).map_err(|_| self.eof(what))
    }

    /// A little-endian `u64` (`size_t`).
    pub(crate) fn bin_u64(&mut self, what: &str) -> Result<u64, Error> {
        let b = self.take(8, what)?;
        let r: IResult<&[u8], u64> = nom::number::complete::le_u64(b);
        r.map(|(_, v)| v).map_err(|_| self.eof(what))
    }

    /// A little-endian `f64`.
    pub(crate) fn bin_f64(&mut self, what: &str) -> Result<f64, Error> {
        let b = self.take(8, what)?;
        let r: IResult<&[u8], f64> = nom::number::complete::le_f64(b);
        r.map(|(_, v)| v).map_err(|_| self.eof(what))
    }
}

/// `"x"` → "`x`", shortened when long.
pub(crate) fn quote(text: &str) -> String {
    let mut s: String = text.chars().take(40).collect();
    if s.len() < text.len() {
        s.push('…');
    }
    format!("`{s}`")
}

/// An unsigned integer (the whole text).
pub(crate) fn parse_u64(text: &str) -> Option<u64> {
    all_consuming(nom::character::complete::u64::<&str, nom::error::Error<&str>>)
        .parse(text)
        .ok()
        .map(|(_, v)| v)
}

/// A signed integer (the whole text).
pub(crate) fn parse_i64(text: &str) -> Option<i64> {
    all_consuming(nom::character::complete::i64::<&str, nom::error::Error<&str>>)
        .parse(text)
        .ok()
        .map(|(_, v)| v)
}

/// A floating-point number (the whole text; may be NaN or infinite).
pub(crate) fn parse_f64(text: &str) -> Option<f64> {
    all_consuming(nom::number::complete::double::<&str, nom::error::Error<&str>>)
        .parse(text)
        .ok()
        .map(|(_, v)| v)
}

/// The byte offset of the first `//` or `/*` in `w` (a byte scan: this runs on every token).
fn comment_start(w: &[u8]) -> Option<usize> {
    let first = |second: u8| {
        w.windows(2)
            .position(|pair| pair[0] == b'/' && pair[1] == second)
    };
    match (first(b'/'), first(b'*')) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}
