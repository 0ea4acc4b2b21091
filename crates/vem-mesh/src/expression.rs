//! Expressions of position: loads, prescribed displacements, gaps and friction bounds written
//! in scene files as formulas of `x`, `y`, `z` (the coordinates) and `t` (pseudo-time of a load
//! history).
//!
//! The grammar is the usual one of mathematics: `+ - * /`, `^` (right-associative, binding
//! tighter than a unary minus: `-x^2 = -(x^2)`, `2^3^2 = 2^9`), parentheses, numbers in
//! decimal or exponent notation, the constants `pi` and `e`, and the functions `sin cos tan asin
//! acos atan sinh cosh tanh exp ln log log10 sqrt abs floor ceil sign` of one argument and `atan2
//! min max pow` of two. An expression is compiled once into a stack program and evaluated
//! without allocation. (A general-purpose expression crate was tried first: it read `-x^2` as
//! `(-x)^2`, a silently different model; hence this small, fully specified grammar.)
//!
//! ```
//! use vem_mesh::expression::Expression;
//! let g = Expression::parse("0.3 * (1 + x^2) - sin(pi * y / 2)")?;
//! assert!((g.eval_at(&[1.0, 1.0], 0.0) - (0.6 - 1.0)).abs() < 1e-15);
//! assert_eq!(Expression::parse("-x^2")?.eval_at(&[3.0, 0.0], 0.0), -9.0);
//! let err = Expression::parse("2 * (x + ").unwrap_err();
//! assert_eq!(err.to_string(), "expression '2 * (x + ', column 10: a value is missing after '+'");
//! # Ok::<(), vem_mesh::expression::ExpressionError>(())
//! ```

use std::fmt;

/// A compiled expression of `x`, `y`, `z` and `t`. Two expressions are equal when they are
/// written alike.
#[derive(Debug, Clone)]
pub struct Expression {
    source: String,
    program: Vec<Op>,
    uses: [bool; 4],
}

/// Why an expression was refused: the text, the column (1-based, in characters) and what is
/// wrong there.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("expression '{text}', column {column}: {message}")]
pub struct ExpressionError {
    /// The expression as written.
    pub text: String,
    /// Where (1-based character column).
    pub column: usize,
    /// What is wrong.
    pub message: String,
}

#[derive(Debug, Clone, Copy)]
enum Op {
    Number(f64),
    /// Variable 0..4: x, y, z, t.
    Variable(usize),
    Negate,
    Add,
    Subtract,
    Multiply,
    Divide,
    Power,
    Unary(fn(f64) -> f64),
    Binary(fn(f64, f64) -> f64),
}

const VARIABLES: [&str; 4] = ["x", "y", "z", "t"];

fn unary(name: &str) -> Option<fn(f64) -> f64> {
    Some(match name {
        "sin" => f64::sin,
        "cos" => f64::cos,
        "tan" => f64::tan,
        "asin" => f64::asin,
        "acos" => f64::acos,
        "atan" => f64::atan,
        "sinh" => f64::sinh,
        "cosh" => f64::cosh,
        "tanh" => f64::tanh,
        "exp" => f64::exp,
        "ln" | "log" => f64::ln,
        "log10" => f64::log10,
        "sqrt" => f64::sqrt,
        "abs" => f64::abs,
        "floor" => f64::floor,
        "ceil" => f64::ceil,
        "sign" => |v: f64| {
            if v > 0.0 {
                1.0
            } else if v < 0.0 {
                -1.0
            } else {
                0.0
            }
        },
        _ => return None,
    })
}

fn binary(name: &str) -> Option<fn(f64, f64) -> f64> {
    Some(match name {
        "atan2" => f64::atan2,
        "min" => f64::min,
        "max" => f64::max,
        "pow" => f64::powf,
        _ => return None,
    })
}

#[derive(Debug, Clone, PartialEq)]
enum Token {
    Number(f64),
    Name(String),
    Symbol(char),
}

struct Parser<'a> {
    source: &'a str,
    tokens: Vec<(Token, usize)>,
    position: usize,
    program: Vec<Op>,
    uses: [bool; 4],
    depth: usize,
}

impl Expression {
    /// Parses and compiles `source`.
    ///
    /// # Errors
    /// [`ExpressionError`] naming the column: an unknown name, a missing value or parenthesis,
    /// a function with the wrong number of arguments, an unreadable number.
    pub fn parse(source: &str) -> Result<Self, ExpressionError> {
        let mut parser = Parser {
            source,
            tokens: tokenize(source)?,
            position: 0,
            program: Vec::new(),
            uses: [false; 4],
            depth: 0,
        };
        if parser.tokens.is_empty() {
            return Err(parser.error_at(1, "the expression is empty"));
        }
        parser.sum()?;
        if let Some((token, column)) = parser.tokens.get(parser.position) {
            let what = describe(token);
            return Err(parser.error_at(*column, &format!("unexpected {what}")));
        }
        // The evaluation stack is fixed: refuse a program that would need more.
        let mut depth = 0usize;
        for op in &parser.program {
            match op {
                Op::Number(_) | Op::Variable(_) => depth += 1,
                Op::Negate | Op::Unary(_) => {}
                _ => depth -= 1,
            }
            if depth > STACK {
                return Err(parser.error_at(1, "the expression is nested too deeply"));
            }
        }
        Ok(Self {
            source: source.to_string(),
            program: parser.program,
            uses: parser.uses,
        })
    }

    /// The expression as written.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// Whether the expression uses the pseudo-time `t`.
    pub fn uses_time(&self) -> bool {
        self.uses[3]
    }

    /// The highest coordinate the expression uses (0 when none, 1 for `x`, 2 for `y`, 3 for
    /// `z`): a 2D body cannot take an expression of `z`.
    pub fn dimension_used(&self) -> usize {
        (0..3).rev().find(|&k| self.uses[k]).map_or(0, |k| k + 1)
    }

    /// The value at the point with coordinates `coordinates` (`x`, `y`, `z`; missing ones are
    /// zero) and pseudo-time `t`.
    pub fn eval_at(&self, coordinates: &[f64], t: f64) -> f64 {
        let variables = [
            coordinates.first().copied().unwrap_or(0.0),
            coordinates.get(1).copied().unwrap_or(0.0),
            coordinates.get(2).copied().unwrap_or(0.0),
            t,
        ];
        let mut stack = [0.0f64; STACK];
        let mut top = 0usize;
        for op in &self.program {
            match *op {
                Op::Number(v) => {
                    stack[top] = v;
                    top += 1;
                }
                Op::Variable(k) => {
                    stack[top] = variables[k];
                    top += 1;
                }
                Op::Negate => stack[top - 1] = -stack[top - 1],
                Op::Unary(f) => stack[top - 1] = f(stack[top - 1]),
                op => {
                    let (a, b) = (stack[top - 2], stack[top - 1]);
                    top -= 1;
                    stack[top - 1] = match op {
                        Op::Add => a + b,
                        Op::Subtract => a - b,
                        Op::Multiply => a * b,
                        Op::Divide => a / b,
                        Op::Power => a.powf(b),
                        Op::Binary(f) => f(a, b),
                        _ => unreachable!("the other operations take one operand"),
                    };
                }
            }
        }
        stack[0]
    }
}

impl PartialEq for Expression {
    fn eq(&self, other: &Self) -> bool {
        self.source == other.source
    }
}

impl fmt::Display for Expression {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.source)
    }
}

/// The deepest nesting of the parser (parentheses, signs, exponents): deeper is refused.
const MAX_DEPTH: usize = 60;
/// The size of the evaluation stack.
const STACK: usize = 64;

fn describe(token: &Token) -> String {
    match token {
        Token::Number(v) => format!("number {v}"),
        Token::Name(n) => format!("name '{n}'"),
        Token::Symbol(c) => format!("'{c}'"),
    }
}

fn tokenize(source: &str) -> Result<Vec<(Token, usize)>, ExpressionError> {
    let chars: Vec<char> = source.chars().collect();
    let error = |column: usize, message: String| ExpressionError {
        text: source.to_string(),
        column,
        message,
    };
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let column = i + 1;
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_digit() || c == '.' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    while j < chars.len() && chars[j].is_ascii_digit() {
                        j += 1;
                    }
                    i = j;
                }
            }
            let text: String = chars[start..i].iter().collect();
            let value: f64 = text
                .parse()
                .map_err(|_| error(column, format!("'{text}' is not a number")))?;
            if !value.is_finite() {
                return Err(error(column, format!("'{text}' overflows")));
            }
            tokens.push((Token::Number(value), column));
        } else if c.is_ascii_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            tokens.push((Token::Name(chars[start..i].iter().collect()), column));
        } else if "+-*/^(),".contains(c) {
            tokens.push((Token::Symbol(c), column));
            i += 1;
        } else {
            return Err(error(column, format!("'{c}' is not part of an expression")));
        }
    }
    Ok(tokens)
}

impl Parser<'_> {
    fn error_at(&self, column: usize, message: &str) -> ExpressionError {
        ExpressionError {
            text: self.source.to_string(),
            column,
            message: message.to_string(),
        }
    }

    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.position).map(|(t, _)| t)
    }

    fn column(&self) -> usize {
        self.tokens
            .get(self.position)
            .map_or(self.source.chars().count() + 1, |(_, c)| *c)
    }

    fn emit(&mut self, op: Op) -> Result<(), ExpressionError> {
        self.program.push(op);
        if self.program.len() > 4 * MAX_DEPTH {
            return Err(self.error_at(self.column(), "the expression is too long"));
        }
        Ok(())
    }

    fn eat(&mut self, symbol: char) -> bool {
        if self.peek() == Some(&Token::Symbol(symbol)) {
            self.position += 1;
            true
        } else {
            false
        }
    }

    /// sum := product (('+' | '-') product)*
    fn sum(&mut self) -> Result<(), ExpressionError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(self.error_at(self.column(), "the expression is nested too deeply"));
        }
        let result = self.sum_terms();
        self.depth -= 1;
        result
    }

    fn sum_terms(&mut self) -> Result<(), ExpressionError> {
        self.product()?;
        loop {
            let op = if self.eat('+') {
                Op::Add
            } else if self.eat('-') {
                Op::Subtract
            } else {
                return Ok(());
            };
            self.expect_value(if matches!(op, Op::Add) { '+' } else { '-' })?;
            self.product()?;
            self.emit(op)?;
        }
    }

    /// product := signed (('*' | '/') signed)*
    fn product(&mut self) -> Result<(), ExpressionError> {
        self.signed()?;
        loop {
            let (op, symbol) = if self.eat('*') {
                (Op::Multiply, '*')
            } else if self.eat('/') {
                (Op::Divide, '/')
            } else {
                return Ok(());
            };
            self.expect_value(symbol)?;
            self.signed()?;
            self.emit(op)?;
        }
    }

    /// signed := '-' signed | '+' signed | power
    fn signed(&mut self) -> Result<(), ExpressionError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(self.error_at(self.column(), "the expression is nested too deeply"));
        }
        let result = self.signed_value();
        self.depth -= 1;
        result
    }

    fn signed_value(&mut self) -> Result<(), ExpressionError> {
        if self.eat('-') {
            self.expect_value('-')?;
            self.signed()?;
            self.emit(Op::Negate)
        } else if self.eat('+') {
            self.expect_value('+')?;
            self.signed()
        } else {
            self.power()
        }
    }

    /// power := atom ('^' signed)?   (right-associative; the exponent may carry a sign)
    fn power(&mut self) -> Result<(), ExpressionError> {
        self.atom()?;
        if self.eat('^') {
            self.expect_value('^')?;
            self.signed()?;
            self.emit(Op::Power)?;
        }
        Ok(())
    }

    fn expect_value(&self, after: char) -> Result<(), ExpressionError> {
        match self.peek() {
            None | Some(Token::Symbol(')' | ',' | '*' | '/' | '^')) => Err(self.error_at(
                self.column(),
                &format!("a value is missing after '{after}'"),
            )),
            _ => Ok(()),
        }
    }

    fn atom(&mut self) -> Result<(), ExpressionError> {
        let column = self.column();
        let Some((token, _)) = self.tokens.get(self.position).cloned() else {
            return Err(self.error_at(column, "a value is missing at the end"));
        };
        self.position += 1;
        match token {
            Token::Number(v) => self.emit(Op::Number(v)),
            Token::Symbol('(') => {
                self.sum()?;
                if !self.eat(')') {
                    return Err(self.error_at(self.column(), "')' is missing"));
                }
                Ok(())
            }
            Token::Symbol(c) => Err(self.error_at(column, &format!("unexpected '{c}'"))),
            Token::Name(name) => {
                if self.eat('(') {
                    let arguments = self.arguments(&name)?;
                    if let (Some(f), 1) = (unary(&name), arguments) {
                        return self.emit(Op::Unary(f));
                    }
                    if let (Some(f), 2) = (binary(&name), arguments) {
                        return self.emit(Op::Binary(f));
                    }
                    let expected = if unary(&name).is_some() {
                        "1 argument"
                    } else if binary(&name).is_some() {
                        "2 arguments"
                    } else {
                        return Err(self.error_at(column, &format!("unknown function '{name}'")));
                    };
                    return Err(self.error_at(
                        column,
                        &format!("'{name}' takes {expected}, not {arguments}"),
                    ));
                }
                if let Some(k) = VARIABLES.iter().position(|v| *v == name) {
                    self.uses[k] = true;
                    return self.emit(Op::Variable(k));
                }
                match name.as_str() {
                    "pi" => self.emit(Op::Number(std::f64::consts::PI)),
                    "e" => self.emit(Op::Number(std::f64::consts::E)),
                    _ => Err(self.error_at(
                        column,
                        &format!("unknown name '{name}' (use x, y, z, t, pi, e)"),
                    )),
                }
            }
        }
    }

    /// The arguments of a call after its '(' up to ')', their count.
    fn arguments(&mut self, name: &str) -> Result<usize, ExpressionError> {
        let mut count = 0;
        if self.eat(')') {
            return Ok(0);
        }
        loop {
            self.sum()?;
            count += 1;
            if self.eat(')') {
                return Ok(count);
            }
            if !self.eat(',') {
                return Err(self.error_at(
                    self.column(),
                    &format!("')' is missing after the arguments of '{name}'"),
                ));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn value(source: &str, x: f64, y: f64) -> f64 {
        Expression::parse(source).unwrap().eval_at(&[x, y], 0.5)
    }

    #[test]
    fn precedence_and_associativity_follow_mathematics() {
        assert_eq!(value("-x^2", 3.0, 0.0), -9.0);
        assert_eq!(value("2^3^2", 0.0, 0.0), 512.0);
        assert_eq!(value("2^-1", 0.0, 0.0), 0.5);
        assert_eq!(value("1 - 2 - 3", 0.0, 0.0), -4.0);
        assert_eq!(value("8 / 4 / 2", 0.0, 0.0), 1.0);
        assert_eq!(value("1 + 2 * 3", 0.0, 0.0), 7.0);
        assert_eq!(value("(1 + 2) * 3", 0.0, 0.0), 9.0);
        assert_eq!(value("--x", 2.0, 0.0), 2.0);
        assert_eq!(value("x * -y", 2.0, 3.0), -6.0);
        assert_eq!(value("t", 0.0, 0.0), 0.5);
        assert_eq!(value("1.5e-3 + 2E2", 0.0, 0.0), 200.0015);
        assert!((value("atan2(y, x) - pi / 4", 1.0, 1.0)).abs() < 1e-15);
        assert_eq!(
            value("max(x, y) + min(x, y) + abs(-2) + sign(-3)", 1.0, 5.0),
            7.0
        );
        assert!((value("sqrt(x^2 + y^2)", 3.0, 4.0) - 5.0).abs() < 1e-15);
        assert!((value("ln(e) + log10(100) + exp(0) + cos(0)", 0.0, 0.0) - 5.0).abs() < 1e-15);
    }

    #[test]
    fn what_an_expression_uses() {
        let e = Expression::parse("x + t").unwrap();
        assert!(e.uses_time());
        assert_eq!(e.dimension_used(), 1);
        assert_eq!(Expression::parse("z").unwrap().dimension_used(), 3);
        assert_eq!(Expression::parse("2").unwrap().dimension_used(), 0);
    }

    #[test]
    fn errors_name_the_column() {
        let cases = [
            ("", 1, "the expression is empty"),
            ("1 +", 4, "a value is missing after '+'"),
            ("(x", 3, "')' is missing"),
            ("foo(x)", 1, "unknown function 'foo'"),
            ("sin(x, y)", 1, "'sin' takes 1 argument, not 2"),
            ("max(x)", 1, "'max' takes 2 arguments, not 1"),
            ("x y", 3, "unexpected name 'y'"),
            ("r + 1", 1, "unknown name 'r' (use x, y, z, t, pi, e)"),
            ("2 # 3", 3, "'#' is not part of an expression"),
            ("1e400", 1, "'1e400' overflows"),
            ("1..2", 1, "'1..2' is not a number"),
            ("x * * 2", 5, "a value is missing after '*'"),
            (")", 1, "unexpected ')'"),
        ];
        for (source, column, message) in cases {
            let err = Expression::parse(source).unwrap_err();
            assert_eq!(
                (err.column, err.message.as_str()),
                (column, message),
                "{source}"
            );
        }
    }

    #[test]
    fn deep_nesting_is_refused_not_overflowed() {
        let deep = format!("{}x{}", "(".repeat(500), ")".repeat(500));
        assert!(Expression::parse(&deep).is_err());
        let long = vec!["x"; 1000].join(" + ");
        assert!(Expression::parse(&long).is_err());
        // Within the limits: evaluated exactly.
        for chain in ["x^".repeat(200) + "x", "-".repeat(100_000) + "x"] {
            assert!(Expression::parse(&chain).is_err());
        }
        let fine = format!("{}x{}", "(".repeat(20), ")".repeat(20));
        assert_eq!(Expression::parse(&fine).unwrap().eval_at(&[2.0], 0.0), 2.0);
    }
}
