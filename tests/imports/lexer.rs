//! Rust source to the few tokens the import scan needs: identifiers, `::`, braces, `;`, `,`,
//! `*`, `#`, `=` and string literals (kept for `#[path = "…"]`). Comments, character literals,
//! lifetimes and numbers are dropped, so a `crate::x` inside a comment or a message is not an
//! import.

#[derive(Clone, Debug, PartialEq)]
pub enum Tok {
    Ident(String),
    PathSep,
    Open,
    Close,
    /// Any other punctuation character.
    Punct(char),
    Str(String),
}

#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    pub tok: Tok,
    /// 1-based line of the token's start.
    pub line: usize,
}

pub fn tokens(src: &str) -> Vec<Token> {
    let chars: Vec<char> = src.chars().collect();
    let mut out = Vec::new();
    let (mut i, mut line) = (0, 1);
    while i < chars.len() {
        let c = chars[i];
        let start_line = line;
        let mut push = |tok| {
            out.push(Token {
                tok,
                line: start_line,
            })
        };
        if c == '\n' {
            line += 1;
            i += 1;
        } else if c.is_whitespace() {
            i += 1;
        } else if c == '/' && chars.get(i + 1) == Some(&'/') {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && chars.get(i + 1) == Some(&'*') {
            i = skip_block_comment(&chars, i, &mut line);
        } else if let Some((end, text)) = string_literal(&chars, i) {
            line += chars[i..end].iter().filter(|&&c| c == '\n').count();
            push(Tok::Str(text));
            i = end;
        } else if c == '\'' {
            i = skip_char_or_lifetime(&chars, i);
        } else if c.is_alphabetic() || c == '_' {
            let end = ident_end(&chars, i);
            push(Tok::Ident(chars[i..end].iter().collect()));
            i = end;
        } else if c.is_ascii_digit() {
            i = ident_end(&chars, i);
        } else if c == ':' && chars.get(i + 1) == Some(&':') {
            push(Tok::PathSep);
            i += 2;
        } else {
            push(match c {
                '{' => Tok::Open,
                '}' => Tok::Close,
                _ => Tok::Punct(c),
            });
            i += 1;
        }
    }
    out
}

fn ident_end(chars: &[char], mut i: usize) -> usize {
    while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
        i += 1;
    }
    i
}

/// Past a block comment starting at `i` (they nest in Rust).
fn skip_block_comment(chars: &[char], mut i: usize, line: &mut usize) -> usize {
    let mut depth = 0;
    while i < chars.len() {
        if chars[i] == '/' && chars.get(i + 1) == Some(&'*') {
            depth += 1;
            i += 2;
        } else if chars[i] == '*' && chars.get(i + 1) == Some(&'/') {
            depth -= 1;
            i += 2;
            if depth == 0 {
                break;
            }
        } else {
            *line += (chars[i] == '\n') as usize;
            i += 1;
        }
    }
    i
}

/// A string literal at `i` (`"…"`, `b"…"`, `c"…"`, `r#"…"#`, `br"…"`): its end and its text
/// (escapes left as written). None when `i` does not start one. `i` starts a token, so a `b`
/// or `r` there is not the end of an identifier.
fn string_literal(chars: &[char], i: usize) -> Option<(usize, String)> {
    let at = |k: usize| chars.get(k).copied();
    let mut j = i;
    if matches!(at(j), Some('b' | 'c')) {
        j += 1;
    }
    let raw = at(j) == Some('r');
    j += raw as usize;
    let hashes = if raw {
        chars[j..].iter().take_while(|&&c| c == '#').count()
    } else {
        0
    };
    j += hashes;
    if at(j) != Some('"') {
        return None;
    }
    let body = j + 1;
    let mut k = body;
    while k < chars.len() {
        if !raw && chars[k] == '\\' {
            k += 2;
        } else if chars[k] == '"' && (1..=hashes).all(|h| at(k + h) == Some('#')) {
            return Some((k + 1 + hashes, chars[body..k].iter().collect()));
        } else {
            k += 1;
        }
    }
    Some((chars.len(), chars[body..].iter().collect()))
}

/// Past a character literal (`'a'`, `'\n'`, `'\u{1F600}'`) or a lifetime (`'a`).
fn skip_char_or_lifetime(chars: &[char], i: usize) -> usize {
    if chars.get(i + 1) == Some(&'\\') {
        let mut k = i + 2;
        while k < chars.len() && chars[k] != '\'' {
            k += 1;
        }
        return k + 1;
    }
    if chars.get(i + 2) == Some(&'\'') {
        return i + 3;
    }
    ident_end(chars, i + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn idents(src: &str) -> Vec<String> {
        tokens(src)
            .into_iter()
            .filter_map(|t| match t.tok {
                Tok::Ident(s) => Some(s),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn comments_strings_chars_and_lifetimes_are_not_code() {
        // Lifetimes (`'a`) are dropped with character literals.
        let src = "// crate::a\n/* crate::b /* nested */ crate::c */ fn f<'a>(x: &'a str) -> char {\n\
                   let s = \"crate::d\"; let r = r#\"crate::\"e\"#; let q = '\\''; let c = '{'; x }";
        assert_eq!(
            idents(src),
            [
                "fn", "f", "x", "str", "char", "let", "s", "let", "r", "let", "q", "let", "c", "x"
            ]
        );
        let braces = tokens(src)
            .iter()
            .filter(|t| matches!(t.tok, Tok::Open | Tok::Close))
            .count();
        assert_eq!(braces, 2, "the '{{' character literal is not a brace");
    }

    #[test]
    fn lines_count_through_comments_and_strings() {
        let t = tokens("/*\n\n*/ a \"x\ny\" b\nc");
        let lines: Vec<usize> = t.iter().map(|t| t.line).collect();
        assert_eq!(lines, [3, 3, 4, 5]);
        assert_eq!(t[1].tok, Tok::Str("x\ny".into()));
    }

    #[test]
    fn path_separators_and_attribute_strings() {
        let t = tokens("#[path = \"x_tests.rs\"] mod x; use a::b;");
        assert!(t.contains(&Token {
            tok: Tok::Str("x_tests.rs".into()),
            line: 1
        }));
        assert_eq!(t.iter().filter(|t| t.tok == Tok::PathSep).count(), 1);
    }
}
