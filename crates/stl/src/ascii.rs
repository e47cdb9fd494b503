//! ASCII STL: `solid`, facets of three vertices, `endsolid`; each problem located by line.

use std::fmt;

use glam::DVec3;

use crate::check::{accept, first_non_finite, Origin};
use crate::error::{Location, StlError};
use crate::mesh::{Format, Mesh, Triangle};
use crate::tokens::{Token, Tokens};
use crate::transform::Transform;

/// Reads the text of a file that detection took for ASCII STL.
pub(crate) fn parse_ascii(text: &str, file: &str, transform: &Transform) -> Result<Mesh, StlError> {
    Parser {
        tokens: Tokens::new(text),
        file,
        transform,
        triangles: Vec::new(),
    }
    .solids()
}

/// The vertex or normal whose numbers are being read, named in messages.
#[derive(Debug, Clone, Copy)]
enum Item {
    /// The normal of a triangle (counted from 1).
    Normal { triangle: usize },
    /// A vertex (counted from 1) of a triangle (counted from 1).
    Vertex { triangle: usize, vertex: usize },
}

impl fmt::Display for Item {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Item::Normal { triangle } => {
                write!(f, "the normal of triangle {triangle} (counting from 1)")
            }
            Item::Vertex { triangle, vertex } => {
                write!(
                    f,
                    "vertex {vertex} of triangle {triangle} (counting from 1)"
                )
            }
        }
    }
}

/// A recursive-descent reader over the file's words.
struct Parser<'a, 't> {
    tokens: Tokens<'a>,
    file: &'t str,
    transform: &'t Transform,
    triangles: Vec<Triangle>,
}

impl<'a> Parser<'a, '_> {
    /// One or more `solid … endsolid` blocks, then the end of the file.
    fn solids(mut self) -> Result<Mesh, StlError> {
        let first = self.next_or_end("`solid`")?;
        if !first.is("solid") {
            return Err(self.unexpected(first, "`solid`"));
        }
        let name = self.solid_name(first.line);
        let mut last_end = self.solid_body()?;
        while let Some(token) = self.tokens.next() {
            if !token.is("solid") {
                return Err(self.unexpected(token, "`solid` or the end of the file"));
            }
            self.solid_name(token.line);
            last_end = self.solid_body()?;
        }
        if self.triangles.is_empty() {
            return Err(StlError::AsciiNoTriangles {
                file: self.file.into(),
                line: last_end,
            });
        }
        Ok(Mesh {
            triangles: self.triangles,
            name,
            format: Format::Ascii,
        })
    }

    /// The words after `solid` on its line, up to a `facet` or `endsolid` there; `None` when
    /// there are none.
    fn solid_name(&mut self, line: usize) -> Option<String> {
        let mut words = Vec::new();
        while let Some(token) = self.tokens.peek() {
            if token.line != line || token.is("facet") || token.is("endsolid") {
                break;
            }
            words.push(token.text);
            self.tokens.next();
        }
        (!words.is_empty()).then(|| words.join(" "))
    }

    /// Facets up to `endsolid`; returns the line of `endsolid`.
    fn solid_body(&mut self) -> Result<usize, StlError> {
        loop {
            let token = self.next_or_end("`facet` or `endsolid`")?;
            if token.is("facet") {
                self.facet(token.line)?;
            } else if token.is("endsolid") {
                self.skip_end_name(token.line);
                return Ok(token.line);
            } else {
                return Err(self.unexpected(token, "`facet` or `endsolid`"));
            }
        }
    }

    /// Skips the optional name after `endsolid` on its line (it need not match the `solid`
    /// name: exporters differ), stopping at a following `solid`.
    fn skip_end_name(&mut self, line: usize) {
        while let Some(token) = self.tokens.peek() {
            if token.line != line || token.is("solid") {
                break;
            }
            self.tokens.next();
        }
    }

    /// `normal n n n outer loop <vertices> endloop endfacet`, after `facet` on `facet_line`.
    fn facet(&mut self, facet_line: usize) -> Result<(), StlError> {
        let triangle = self.triangles.len() + 1;
        self.expect("normal", "`normal` after `facet`")?;
        // The normal's values are ignored: the vertex order defines the normal.
        self.numbers(Item::Normal { triangle })?;
        self.expect("outer", "`outer loop`")?;
        self.expect("loop", "`loop` after `outer`")?;
        let vertices = self.vertices(triangle)?;
        self.expect("endfacet", "`endfacet` after `endloop`")?;
        let origin = Origin {
            file: self.file,
            triangle,
            location: Location::Line(facet_line),
        };
        let metres = accept(origin, vertices, self.transform)?;
        self.triangles.push(metres);
        Ok(())
    }

    /// `vertex x y z` lines up to `endloop`; exactly three of them.
    fn vertices(&mut self, triangle: usize) -> Result<Triangle, StlError> {
        let mut vertices = [DVec3::ZERO; 3];
        let mut count = 0;
        loop {
            let token = self.next_or_end("`vertex` or `endloop`")?;
            if token.is("vertex") {
                count += 1;
                let point = self.vertex(triangle, count)?;
                if let Some(slot) = vertices.get_mut(count - 1) {
                    *slot = point;
                }
            } else if token.is("endloop") {
                if count != 3 {
                    return Err(StlError::VertexCount {
                        file: self.file.into(),
                        line: token.line,
                        triangle,
                        count,
                    });
                }
                return Ok(vertices);
            } else {
                return Err(self.unexpected(token, "`vertex` or `endloop`"));
            }
        }
    }

    /// The three finite coordinates after `vertex`.
    fn vertex(&mut self, triangle: usize, vertex: usize) -> Result<DVec3, StlError> {
        let numbers = self.numbers(Item::Vertex { triangle, vertex })?;
        let point = DVec3::from_array(numbers.map(|(value, _)| value));
        match first_non_finite(point) {
            None => Ok(point),
            Some((axis, i)) => {
                let token = numbers[i].1;
                Err(StlError::NonFinite {
                    file: self.file.into(),
                    triangle,
                    location: Location::Line(token.line),
                    vertex,
                    axis,
                    value: token.shown(),
                })
            }
        }
    }

    /// Exactly three numbers, each with its token; a fourth on the same line is an error.
    fn numbers(&mut self, item: Item) -> Result<[(f64, Token<'a>); 3], StlError> {
        let mut numbers = [(0.0, Token { text: "", line: 0 }); 3];
        for (found, slot) in numbers.iter_mut().enumerate() {
            let token = self.next_or_end("a number")?;
            *slot = (self.number(token, item, found)?, token);
        }
        // A number on the same line as the third is a fourth; one on a later line is left to
        // the caller, whose message ("expected `vertex`…") fits a missing keyword better.
        let last_line = numbers[2].1.line;
        let extra = self.tokens.peek();
        if let Some(extra) = extra.filter(|t| t.line == last_line && t.number().is_some()) {
            return Err(StlError::ExtraNumber {
                file: self.file.into(),
                line: extra.line,
                item: item.to_string(),
                token: extra.shown(),
            });
        }
        Ok(numbers)
    }

    /// The token as a number; a keyword means numbers are missing, anything else is unreadable.
    fn number(&self, token: Token<'_>, item: Item, found: usize) -> Result<f64, StlError> {
        if let Some(value) = token.number() {
            return Ok(value);
        }
        Err(if token.is_keyword() {
            StlError::MissingNumbers {
                file: self.file.into(),
                line: token.line,
                item: item.to_string(),
                found,
                next: token.shown(),
            }
        } else {
            StlError::BadNumber {
                file: self.file.into(),
                line: token.line,
                item: item.to_string(),
                token: token.shown(),
            }
        })
    }

    /// Consumes the next word, which must be `keyword`.
    fn expect(&mut self, keyword: &str, expected: &'static str) -> Result<(), StlError> {
        let token = self.next_or_end(expected)?;
        if token.is(keyword) {
            Ok(())
        } else {
            Err(self.unexpected(token, expected))
        }
    }

    /// The next word, or an error saying the file ended where `expected` should follow.
    fn next_or_end(&mut self, expected: &'static str) -> Result<Token<'a>, StlError> {
        self.tokens.next().ok_or_else(|| StlError::UnexpectedEnd {
            file: self.file.into(),
            line: self.tokens.line(),
            expected,
        })
    }

    /// The error for a word the grammar does not allow here.
    fn unexpected(&self, token: Token<'_>, expected: &'static str) -> StlError {
        StlError::Unexpected {
            file: self.file.into(),
            line: token.line,
            expected,
            found: token.shown(),
        }
    }
}
