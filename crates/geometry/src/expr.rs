//! Density expressions in x and y (`--density`), e.g. `1 + 10*exp(-((x-0.5)^2+y^2)/0.01)`.
//!
//! Grammar (usual precedence; `^` is right-associative and binds tighter than unary minus,
//! so `-x^2 = -(x^2)` and `2^3^2 = 2^9`):
//!
//! ```text
//! sum     := product (('+' | '-') product)*
//! product := unary (('*' | '/') unary)*
//! unary   := ('-' | '+') unary | power
//! power   := atom ('^' unary)?
//! atom    := number | 'x' | 'y' | 'pi' | 'e' | name '(' sum (',' sum)* ')' | '(' sum ')'
//! ```
//!
//! Functions: `exp log sqrt sin cos tan tanh abs` (one argument), `min max` (two or more: the smallest of several sources' sizes).
use crate::density::Density;
use glam::DVec2;
use std::sync::Arc;
use thiserror::Error;

/// A syntax error in an expression, with the 1-based column (in characters) where it was found.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
#[error("column {column}: {message}")]
pub struct ExprError {
    /// What is wrong.
    pub message: String,
    /// 1-based column of the offending character (one past the end for "unexpected end").
    pub column: usize,
}

/// A parsed expression in `x` and `y`, ready to evaluate.
#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    root: Node,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Func1 {
    Exp,
    Log,
    Sqrt,
    Sin,
    Cos,
    Tan,
    Tanh,
    Abs,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Func2 {
    Min,
    Max,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
}

#[derive(Clone, Debug, PartialEq)]
enum Node {
    Num(f64),
    X,
    Y,
    Neg(Box<Node>),
    Bin(BinOp, Box<Node>, Box<Node>),
    Call1(Func1, Box<Node>),
    Call2(Func2, Box<Node>, Box<Node>),
}

impl Node {
    fn eval(&self, p: DVec2) -> f64 {
        match self {
            Node::Num(v) => *v,
            Node::X => p.x,
            Node::Y => p.y,
            Node::Neg(a) => -a.eval(p),
            Node::Bin(op, a, b) => {
                let (a, b) = (a.eval(p), b.eval(p));
                match op {
                    BinOp::Add => a + b,
                    BinOp::Sub => a - b,
                    BinOp::Mul => a * b,
                    BinOp::Div => a / b,
                    BinOp::Pow => a.powf(b),
                }
            }
            Node::Call1(f, a) => {
                let a = a.eval(p);
                match f {
                    Func1::Exp => a.exp(),
                    Func1::Log => a.ln(),
                    Func1::Sqrt => a.sqrt(),
                    Func1::Sin => a.sin(),
                    Func1::Cos => a.cos(),
                    Func1::Tan => a.tan(),
                    Func1::Tanh => a.tanh(),
                    Func1::Abs => a.abs(),
                }
            }
            Node::Call2(f, a, b) => {
                let (a, b) = (a.eval(p), b.eval(p));
                match f {
                    Func2::Min => a.min(b),
                    Func2::Max => a.max(b),
                }
            }
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Num(f64),
    Ident(String),
    Op(char),
    End,
}

/// A token and its 1-based column.
type Token = (Tok, usize);

fn tokenize(text: &str) -> Result<Vec<Token>, ExprError> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let col = i + 1;
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_digit()
            || (c == '.' && chars.get(i + 1).is_some_and(|d| d.is_ascii_digit()))
        {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            // An exponent only if digits follow, so that `2e` is the number 2 then the name e.
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    i = j;
                    while i < chars.len() && chars[i].is_ascii_digit() {
                        i += 1;
                    }
                }
            }
            let s: String = chars[start..i].iter().collect();
            let v: f64 = s.parse().map_err(|_| ExprError {
                message: format!("invalid number '{s}'"),
                column: col,
            })?;
            out.push((Tok::Num(v), col));
        } else if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            out.push((Tok::Ident(chars[start..i].iter().collect()), col));
        } else if "+-*/^(),".contains(c) {
            out.push((Tok::Op(c), col));
            i += 1;
        } else {
            return Err(ExprError {
                message: format!("unexpected character '{c}'"),
                column: col,
            });
        }
    }
    out.push((Tok::End, chars.len() + 1));
    Ok(out)
}

/// Deepest nesting of parentheses, signs and exponents accepted, so that hostile input
/// cannot overflow the stack of the recursive-descent parser.
const MAX_DEPTH: usize = 256;

struct Parser {
    toks: Vec<Token>,
    pos: usize,
    depth: usize,
}

impl Parser {
    fn peek(&self) -> &Tok {
        &self.toks[self.pos].0
    }
    fn col(&self) -> usize {
        self.toks[self.pos].1
    }
    fn bump(&mut self) -> Token {
        let t = self.toks[self.pos].clone();
        if self.pos + 1 < self.toks.len() {
            self.pos += 1;
        }
        t
    }
    fn err<T>(&self, message: impl Into<String>) -> Result<T, ExprError> {
        Err(ExprError {
            message: message.into(),
            column: self.col(),
        })
    }
    fn eat(&mut self, op: char) -> bool {
        if *self.peek() == Tok::Op(op) {
            self.bump();
            true
        } else {
            false
        }
    }
    fn expect(&mut self, op: char) -> Result<(), ExprError> {
        if self.eat(op) {
            Ok(())
        } else {
            self.err(format!("expected '{op}'"))
        }
    }

    fn sum(&mut self) -> Result<Node, ExprError> {
        let mut lhs = self.product()?;
        loop {
            let op = match self.peek() {
                Tok::Op('+') => BinOp::Add,
                Tok::Op('-') => BinOp::Sub,
                _ => return Ok(lhs),
            };
            self.bump();
            let rhs = self.product()?;
            lhs = Node::Bin(op, Box::new(lhs), Box::new(rhs));
        }
    }

    fn product(&mut self) -> Result<Node, ExprError> {
        let mut lhs = self.unary()?;
        loop {
            let op = match self.peek() {
                Tok::Op('*') => BinOp::Mul,
                Tok::Op('/') => BinOp::Div,
                _ => return Ok(lhs),
            };
            self.bump();
            if op == BinOp::Mul && *self.peek() == Tok::Op('*') {
                return self.err("'**' is Python's power; here a power is '^' (x^2)");
            }
            let rhs = self.unary()?;
            lhs = Node::Bin(op, Box::new(lhs), Box::new(rhs));
        }
    }

    fn unary(&mut self) -> Result<Node, ExprError> {
        // Every recursive path (parentheses, calls, signs, exponents) passes through here.
        if self.depth >= MAX_DEPTH {
            return self.err(format!(
                "expression nested more than {MAX_DEPTH} levels deep"
            ));
        }
        self.depth += 1;
        let node = self.unary_inner();
        self.depth -= 1;
        node
    }

    fn unary_inner(&mut self) -> Result<Node, ExprError> {
        if self.eat('-') {
            Ok(Node::Neg(Box::new(self.unary()?)))
        } else if self.eat('+') {
            self.unary()
        } else {
            self.power()
        }
    }

    fn power(&mut self) -> Result<Node, ExprError> {
        let base = self.atom()?;
        if self.eat('^') {
            // The exponent is a `unary`, which itself ends in `power`: right-associative, and
            // `2^-1` is allowed.
            let exp = self.unary()?;
            Ok(Node::Bin(BinOp::Pow, Box::new(base), Box::new(exp)))
        } else {
            Ok(base)
        }
    }

    fn atom(&mut self) -> Result<Node, ExprError> {
        let (tok, col) = self.bump();
        match tok {
            Tok::Num(v) => Ok(Node::Num(v)),
            Tok::Op('(') => {
                let inner = self.sum()?;
                self.expect(')')?;
                Ok(inner)
            }
            Tok::Ident(name) => self.name(&name, col),
            Tok::End => Err(ExprError {
                message: "unexpected end of expression".into(),
                column: col,
            }),
            Tok::Op(c) => Err(ExprError {
                message: format!("expected a number, x, y or '(' but found '{c}'"),
                column: col,
            }),
        }
    }

    fn name(&mut self, name: &str, col: usize) -> Result<Node, ExprError> {
        let f1 = match name {
            "x" => return Ok(Node::X),
            "y" => return Ok(Node::Y),
            "pi" => return Ok(Node::Num(std::f64::consts::PI)),
            "e" => return Ok(Node::Num(std::f64::consts::E)),
            "exp" => Some(Func1::Exp),
            "log" => Some(Func1::Log),
            "sqrt" => Some(Func1::Sqrt),
            "sin" => Some(Func1::Sin),
            "cos" => Some(Func1::Cos),
            "tan" => Some(Func1::Tan),
            "tanh" => Some(Func1::Tanh),
            "abs" => Some(Func1::Abs),
            "min" | "max" => None,
            _ => {
                return Err(ExprError {
                    message: format!(
                        "unknown name '{name}' (variables: x, y, pi, e; functions: exp, log, sqrt, \
                         sin, cos, tan, tanh, abs, min, max)"
                    ),
                    column: col,
                })
            }
        };
        if !self.eat('(') {
            return self.err(format!("expected '(' after function '{name}'"));
        }
        let mut args = vec![self.sum()?];
        while self.eat(',') {
            args.push(self.sum()?);
        }
        let arity_error = |message: String| ExprError {
            message,
            column: col,
        };
        match f1 {
            Some(_) if args.len() != 1 => {
                return Err(arity_error(format!(
                    "{name} takes 1 argument, found {}",
                    args.len()
                )))
            }
            None if args.len() < 2 => {
                return Err(arity_error(format!(
                    "{name} takes 2 or more arguments, found {}",
                    args.len()
                )))
            }
            _ => {}
        }
        self.expect(')')?;
        Ok(match f1 {
            Some(f) => Node::Call1(f, Box::new(args.pop().expect("one argument checked above"))),
            None => {
                let f = if name == "min" {
                    Func2::Min
                } else {
                    Func2::Max
                };
                // min(a, b, c, ...) as a balanced tree of pairs: a field of many sources (the
                // smallest of fifty distances) stays a few levels deep.
                let mut level = args;
                while level.len() > 1 {
                    let mut next = Vec::with_capacity(level.len().div_ceil(2));
                    let mut it = level.into_iter();
                    while let Some(a) = it.next() {
                        next.push(match it.next() {
                            Some(b) => Node::Call2(f, Box::new(a), Box::new(b)),
                            None => a,
                        });
                    }
                    level = next;
                }
                level.pop().expect("two or more arguments checked above")
            }
        })
    }
}

impl Expr {
    /// Parse an expression in `x` and `y`. Errors carry the 1-based column of the problem.
    pub fn parse(text: &str) -> Result<Expr, ExprError> {
        let toks = tokenize(text)?;
        let mut p = Parser {
            toks,
            pos: 0,
            depth: 0,
        };
        if *p.peek() == Tok::End {
            return p.err("empty expression");
        }
        let root = p.sum()?;
        match p.peek() {
            Tok::End => Ok(Expr { root }),
            Tok::Op(')') => p.err("unmatched ')'"),
            _ => p.err("expected an operator (+ - * / ^) or the end of the expression"),
        }
    }

    /// Value at `p = (x, y)`. Follows IEEE arithmetic: `log(-1)` is NaN, `1/0` is infinite.
    pub fn eval(&self, p: DVec2) -> f64 {
        self.root.eval(p)
    }
}

impl std::str::FromStr for Expr {
    type Err = ExprError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Expr::parse(s)
    }
}

/// Parse `text` into a [`Density::Function`]. Non-negativity and finiteness on the region
/// cannot be known from the text alone; they are the caller's to check on sample points.
pub fn density_from_expr(text: &str) -> Result<Density, ExprError> {
    let expr = Expr::parse(text)?;
    Ok(Density::Function(Arc::new(move |p| expr.eval(p))))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ev(s: &str, x: f64, y: f64) -> f64 {
        Expr::parse(s)
            .unwrap_or_else(|e| panic!("{s}: {e}"))
            .eval(DVec2::new(x, y))
    }

    fn err(s: &str) -> ExprError {
        Expr::parse(s).expect_err(s)
    }

    #[test]
    fn numbers_and_constants() {
        assert_eq!(ev("1", 0.0, 0.0), 1.0);
        assert_eq!(ev("2.5", 0.0, 0.0), 2.5);
        assert_eq!(ev("1e-3", 0.0, 0.0), 1e-3);
        assert_eq!(ev("1.5E+2", 0.0, 0.0), 150.0);
        assert_eq!(ev(".5", 0.0, 0.0), 0.5);
        assert_eq!(ev("pi", 0.0, 0.0), std::f64::consts::PI);
        assert_eq!(ev("e", 0.0, 0.0), std::f64::consts::E);
        assert_eq!(ev("x", 3.0, 4.0), 3.0);
        assert_eq!(ev("y", 3.0, 4.0), 4.0);
    }

    #[test]
    fn precedence_and_associativity() {
        assert_eq!(ev("1 + 2 * 3", 0.0, 0.0), 7.0);
        assert_eq!(ev("(1 + 2) * 3", 0.0, 0.0), 9.0);
        assert_eq!(ev("8 / 4 / 2", 0.0, 0.0), 1.0);
        assert_eq!(ev("8 - 4 - 2", 0.0, 0.0), 2.0);
        assert_eq!(ev("2^3^2", 0.0, 0.0), 512.0);
        assert_eq!(ev("-x^2", 3.0, 0.0), -9.0);
        assert_eq!(ev("(-x)^2", 3.0, 0.0), 9.0);
        assert_eq!(ev("2^-1", 0.0, 0.0), 0.5);
        assert_eq!(ev("-2*-3", 0.0, 0.0), 6.0);
        assert_eq!(ev("--x", 3.0, 0.0), 3.0);
        assert_eq!(ev("+x", 3.0, 0.0), 3.0);
        assert_eq!(ev("2*x^2*y", 3.0, 2.0), 36.0);
        assert_eq!(ev("1 - x*y/2", 3.0, 2.0), -2.0);
    }

    #[test]
    fn functions() {
        let (x, y) = (0.3, -1.7);
        assert_eq!(ev("exp(x)", x, y), x.exp());
        assert_eq!(ev("log(2)", x, y), 2f64.ln());
        assert_eq!(ev("sqrt(16)", x, y), 4.0);
        assert_eq!(ev("sin(x)+cos(y)", x, y), x.sin() + y.cos());
        assert_eq!(ev("tan(x)", x, y), x.tan());
        assert_eq!(ev("tanh(y)", x, y), y.tanh());
        assert_eq!(ev("abs(y)", x, y), 1.7);
        assert_eq!(ev("min(x, y)", x, y), y);
        assert_eq!(ev("max(x, y)", x, y), x);
        assert_eq!(ev("max(min(x,1), 2*y) + 1", x, y), 1.3);
        // Any number of arguments from two: the smallest of several sources' sizes.
        assert_eq!(ev("min(3, x, 2, y, 5)", x, y), y);
        assert_eq!(ev("max(3, x, 2, y, 5)", x, y), 5.0);
        let fifty: Vec<String> = (0..50).map(|k| format!("{k}+x")).collect();
        assert_eq!(ev(&format!("min({})", fifty.join(",")), x, y), x);
        assert_eq!(ev(&format!("max({})", fifty.join(",")), x, y), 49.0 + x);
        assert_eq!(ev("sqrt(x^2 + y^2)", 3.0, 4.0), 5.0);
        assert!(ev("log(-1)", x, y).is_nan());
    }

    #[test]
    fn paper_style_density_example() {
        let s = "1 + 10*exp(-((x-0.5)^2+y^2)/0.01)";
        let d = density_from_expr(s).unwrap();
        assert!(!d.is_uniform());
        for &(x, y) in &[(0.5, 0.0), (0.0, 0.0), (0.6, 0.05), (-1.0, 1.0)] {
            let want = 1.0 + 10.0 * (-((x - 0.5f64).powi(2) + y * y) / 0.01).exp();
            let got = d.at(DVec2::new(x, y));
            assert!((got - want).abs() <= 1e-15 * want, "{got} vs {want}");
        }
        assert_eq!(d.at(DVec2::new(0.5, 0.0)), 11.0);
    }

    #[test]
    fn errors_report_columns() {
        let e = err("(x + 1");
        assert_eq!(e.column, 7);
        assert_eq!(e.to_string(), "column 7: expected ')'");
        assert_eq!(err("x + * 2").column, 5);
        assert_eq!(err("x + z").column, 5);
        assert!(err("x + z").message.contains("unknown name 'z'"));
        assert_eq!(err("x $ 2").column, 3);
        // Python's power is named, with the one written here.
        let e = err("0.1*x**2");
        assert!(e.message.contains("a power is '^' (x^2)"), "{e}");
        assert_eq!(e.column, 7);
        assert_eq!(err("").column, 1);
        assert_eq!(err("   ").message, "empty expression");
        assert_eq!(err("x)").column, 2);
        assert_eq!(err("x)").message, "unmatched ')'");
        assert_eq!(err("2 x").column, 3);
        assert_eq!(err("sin x").column, 5);
        assert_eq!(err("min(1)").column, 1);
        assert!(err("min(1)").message.contains("2 or more arguments"));
        assert!(err("exp(1, 2)").message.contains("1 argument"));
        assert_eq!(err("1 +").column, 4);
        assert_eq!(err("1..2").column, 1);
        assert_eq!(err("sin(x,").column, 7);
        // Columns count characters, not bytes.
        assert_eq!(err("ρ + 1").column, 1);
        assert_eq!(err("(ρ)").column, 2);
    }

    #[test]
    fn deep_nesting_is_an_error_not_a_stack_overflow() {
        let deep = format!("{}x{}", "(".repeat(100_000), ")".repeat(100_000));
        assert!(err(&deep).message.contains("nested"));
        assert!(err(&"-".repeat(100_000)).message.contains("nested"));
        assert_eq!(
            ev(
                &format!("{}x{}", "(".repeat(100), ")".repeat(100)),
                2.0,
                0.0
            ),
            2.0
        );
    }

    #[test]
    fn from_str_matches_parse() {
        let a: Expr = "x*y".parse().unwrap();
        assert_eq!(a, Expr::parse("x*y").unwrap());
    }

    proptest::proptest! {
        #[test]
        fn arbitrary_text_never_panics(s in "\\PC{0,40}") {
            if let Ok(e) = Expr::parse(&s) {
                let _ = e.eval(DVec2::new(0.25, -0.5));
            }
        }

        #[test]
        fn operator_soup_never_panics(s in "[-+*/^(),xye0-9. ]{0,40}") {
            match Expr::parse(&s) {
                Ok(e) => { let _ = e.eval(DVec2::new(1.5, 2.0)); }
                Err(e) => proptest::prop_assert!(e.column >= 1 && e.column <= s.chars().count() + 1),
            }
        }
    }
}
