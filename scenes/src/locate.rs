//! Finds the line and column of a field path (`objects[2].shape.radius`) in JSON text, so a
//! semantic error can point at the value it is about. A small tokenizer that follows the
//! document's structure; it gives up (None) on anything it does not understand.

/// 1-based (line, column) of the value at `path`, or of its nearest present ancestor.
pub fn locate(text: &str, path: &str) -> Option<(usize, usize)> {
    let want = split_path(path);
    let mut s = Scanner {
        b: text.as_bytes(),
        i: 0,
        line: 1,
        col: 1,
    };
    let mut best = None;
    s.value(&want, 0, &mut best);
    best
}

#[derive(Debug, PartialEq)]
enum Seg {
    Key(String),
    Index(usize),
}

fn split_path(path: &str) -> Vec<Seg> {
    let mut out = Vec::new();
    for part in path.split('.') {
        let mut rest = part;
        if let Some(b) = rest.find('[') {
            if b > 0 {
                out.push(Seg::Key(rest[..b].to_string()));
            }
            rest = &rest[b..];
            while let Some(stripped) = rest.strip_prefix('[') {
                let end = stripped.find(']').unwrap_or(stripped.len());
                if let Ok(i) = stripped[..end].parse() {
                    out.push(Seg::Index(i));
                }
                rest = stripped.get(end + 1..).unwrap_or("");
            }
        } else if !rest.is_empty() {
            out.push(Seg::Key(rest.to_string()));
        }
    }
    out
}

struct Scanner<'a> {
    b: &'a [u8],
    i: usize,
    line: usize,
    col: usize,
}

impl Scanner<'_> {
    fn bump(&mut self) {
        if self.b[self.i] == b'\n' {
            self.line += 1;
            self.col = 1;
        } else if self.b[self.i] & 0xC0 != 0x80 {
            self.col += 1;
        }
        self.i += 1;
    }
    fn ws(&mut self) {
        while self.i < self.b.len() && self.b[self.i].is_ascii_whitespace() {
            self.bump();
        }
    }
    fn peek(&self) -> Option<u8> {
        self.b.get(self.i).copied()
    }
    fn string(&mut self) -> Option<String> {
        let start = self.i + 1;
        self.bump();
        while let Some(c) = self.peek() {
            if c == b'\\' {
                self.bump();
                if self.peek().is_some() {
                    self.bump();
                }
                continue;
            }
            if c == b'"' {
                let s = String::from_utf8_lossy(&self.b[start..self.i]).into_owned();
                self.bump();
                return Some(s);
            }
            self.bump();
        }
        None
    }
    /// Scans one value. While `want[depth..]` is still being followed, records the position of
    /// each matched ancestor into `best`, so the deepest match wins.
    fn value(
        &mut self,
        want: &[Seg],
        depth: usize,
        best: &mut Option<(usize, usize)>,
    ) -> Option<()> {
        self.ws();
        let tracking = depth <= want.len();
        if tracking {
            *best = Some((self.line, self.col));
        }
        match self.peek()? {
            b'{' => {
                self.bump();
                loop {
                    self.ws();
                    match self.peek()? {
                        b'}' => {
                            self.bump();
                            return Some(());
                        }
                        b',' => self.bump(),
                        b'"' => {
                            let key = self.string()?;
                            self.ws();
                            if self.peek()? != b':' {
                                return None;
                            }
                            self.bump();
                            let follow = tracking
                                && matches!(want.get(depth), Some(Seg::Key(k)) if *k == key);
                            if follow {
                                self.value(want, depth + 1, best)?;
                            } else {
                                self.value(want, usize::MAX, &mut None)?;
                            }
                        }
                        _ => return None,
                    }
                }
            }
            b'[' => {
                self.bump();
                let mut index = 0;
                loop {
                    self.ws();
                    match self.peek()? {
                        b']' => {
                            self.bump();
                            return Some(());
                        }
                        b',' => {
                            self.bump();
                            index += 1;
                        }
                        _ => {
                            let follow = tracking
                                && matches!(want.get(depth), Some(Seg::Index(k)) if *k == index);
                            if follow {
                                self.value(want, depth + 1, best)?;
                            } else {
                                self.value(want, usize::MAX, &mut None)?;
                            }
                        }
                    }
                }
            }
            b'"' => self.string().map(|_| ()),
            _ => {
                while let Some(c) = self.peek() {
                    if matches!(c, b',' | b'}' | b']') || c.is_ascii_whitespace() {
                        break;
                    }
                    self.bump();
                }
                Some(())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_nested_fields_and_array_elements() {
        let text = "{\n  \"a\": 1,\n  \"objects\": [\n    {\"r\": 2},\n    {\"shape\": {\"radius\": -1}}\n  ]\n}";
        assert_eq!(locate(text, "objects[1].shape.radius"), Some((5, 26)));
        assert_eq!(locate(text, "a"), Some((2, 8)));
        // A missing field points at its nearest ancestor.
        assert_eq!(locate(text, "objects[0].shape"), Some((4, 5)));
    }
}
