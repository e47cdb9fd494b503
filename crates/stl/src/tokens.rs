//! The words of an ASCII STL file, each with the line it is on.

use std::str::{Lines, SplitAsciiWhitespace};

/// One white-space-separated word of the text.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Token<'a> {
    /// The word as written.
    pub text: &'a str,
    /// Its line, counted from 1.
    pub line: usize,
}

impl Token<'_> {
    /// Whether the word is `keyword`, ignoring ASCII case.
    pub fn is(&self, keyword: &str) -> bool {
        self.text.eq_ignore_ascii_case(keyword)
    }

    /// Whether the word is one of the ASCII STL keywords.
    pub fn is_keyword(&self) -> bool {
        KEYWORDS.iter().any(|k| self.is(k))
    }

    /// The word for an error message: cut after [`SHOWN_CHARS`] characters, with `…` added,
    /// so that a garbage "word" of megabytes does not flood the message.
    pub fn shown(&self) -> String {
        match self.text.char_indices().nth(SHOWN_CHARS) {
            Some((end, _)) => format!("{}…", &self.text[..end]),
            None => self.text.to_string(),
        }
    }

    /// The word read as a number, if it is one (`nan` and `inf` included).
    pub fn number(&self) -> Option<f64> {
        self.text.parse().ok()
    }
}

/// The most characters of a word quoted in an error message.
pub(crate) const SHOWN_CHARS: usize = 40;

/// Every keyword of the ASCII STL grammar.
const KEYWORDS: [&str; 9] = [
    "solid", "facet", "normal", "outer", "loop", "vertex", "endloop", "endfacet", "endsolid",
];

/// The words of a text in order, with one word of look-ahead and the number of the last line
/// seen (for errors at the end of the file).
pub(crate) struct Tokens<'a> {
    lines: Lines<'a>,
    words: SplitAsciiWhitespace<'a>,
    line: usize,
    peeked: Option<Token<'a>>,
}

impl<'a> Tokens<'a> {
    /// The words of `text`.
    pub fn new(text: &'a str) -> Self {
        Self {
            lines: text.lines(),
            words: "".split_ascii_whitespace(),
            line: 0,
            peeked: None,
        }
    }

    /// The next word without consuming it.
    pub fn peek(&mut self) -> Option<Token<'a>> {
        if self.peeked.is_none() {
            self.peeked = self.advance();
        }
        self.peeked
    }

    /// The line of the last word read, or the last line of the text once it is exhausted.
    pub fn line(&self) -> usize {
        self.line.max(1)
    }

    fn advance(&mut self) -> Option<Token<'a>> {
        loop {
            if let Some(text) = self.words.next() {
                return Some(Token {
                    text,
                    line: self.line,
                });
            }
            self.words = self.lines.next()?.split_ascii_whitespace();
            self.line += 1;
        }
    }
}

impl<'a> Iterator for Tokens<'a> {
    type Item = Token<'a>;

    fn next(&mut self) -> Option<Token<'a>> {
        self.peeked.take().or_else(|| self.advance())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_carry_their_lines_across_blank_lines_and_crlf() {
        let words: Vec<(&str, usize)> = Tokens::new("solid a\r\n\r\n  facet  normal\n")
            .map(|t| (t.text, t.line))
            .collect();
        assert_eq!(words, [("solid", 1), ("a", 1), ("facet", 3), ("normal", 3)]);
    }

    #[test]
    fn long_words_are_cut_in_messages() {
        let long = "é".repeat(SHOWN_CHARS + 5);
        let token = Token {
            text: &long,
            line: 1,
        };
        assert_eq!(token.shown(), format!("{}…", "é".repeat(SHOWN_CHARS)));
        assert_eq!(
            Token {
                text: "abc",
                line: 1
            }
            .shown(),
            "abc"
        );
    }

    #[test]
    fn peek_does_not_consume() {
        let mut tokens = Tokens::new("a b");
        assert_eq!(tokens.peek().map(|t| t.text), Some("a"));
        assert_eq!(tokens.next().map(|t| t.text), Some("a"));
        assert_eq!(tokens.next().map(|t| t.text), Some("b"));
        assert_eq!(tokens.next(), None);
    }
}
