#include "frep/hyperfun_syntax.h"

#include <cctype>
#include <cmath>
#include <cstdlib>

#include "base/errors.h"

namespace frep::hyperfun {

std::string located(const std::string& source, Location at, const std::string& what) {
  return source + ":" + std::to_string(at.line) + ":" + std::to_string(at.column) + ": " + what;
}

namespace {

// Parentheses, signs and nested blocks recurse; a hostile program nests them only this deep.
constexpr int kMaxNesting = 200;
// Longer names are an error in HyperFun too.
constexpr std::size_t kMaxNameLength = 128;

struct Token {
  enum class Kind { Number, Name, Symbol, End };
  Kind kind = Kind::End;
  std::string text;  // Name: lower case; Symbol: the characters
  double number = 0.0;
  Location at;
};

class Lexer {
 public:
  Lexer(const std::string& text, const std::string& source) : s_(text), source_(source) {}

  std::vector<Token> tokens() {
    std::vector<Token> out;
    for (;;) {
      skipSpaceAndComments();
      Token t;
      t.at = here();
      if (i_ >= s_.size()) {
        out.push_back(t);
        return out;
      }
      const char c = s_[i_];
      if (std::isdigit(static_cast<unsigned char>(c)) ||
          (c == '.' && i_ + 1 < s_.size() &&
           std::isdigit(static_cast<unsigned char>(s_[i_ + 1])))) {
        t.kind = Token::Kind::Number;
        t.number = number(t.text);
      } else if (std::isalpha(static_cast<unsigned char>(c))) {
        t.kind = Token::Kind::Name;
        while (i_ < s_.size() &&
               (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_')) {
          t.text += static_cast<char>(std::tolower(static_cast<unsigned char>(s_[i_])));
          advance();
        }
        if (t.text.size() > kMaxNameLength)
          throw ModelError(located(source_, t.at,
                                   "a name of " + std::to_string(t.text.size()) +
                                       " characters; at most " + std::to_string(kMaxNameLength)));
      } else {
        t.kind = Token::Kind::Symbol;
        static const char* const pairs[] = {"<=", ">=", "/="};
        for (const char* p : pairs)
          if (s_.compare(i_, 2, p) == 0) t.text = p;
        if (t.text.empty()) {
          if (std::string("+-*/^()[]{},;=<>|&\\~@").find(c) == std::string::npos)
            throw ModelError(located(source_, t.at, "unexpected character " + shown(c)));
          t.text = std::string(1, c);
        }
        for (std::size_t k = 0; k < t.text.size(); ++k) advance();
      }
      out.push_back(t);
    }
  }

 private:
  static std::string shown(char c) {
    if (std::isprint(static_cast<unsigned char>(c))) return std::string("'") + c + "'";
    return "(byte " + std::to_string(static_cast<unsigned char>(c)) + ")";
  }
  Location here() const { return {line_, column_}; }
  void advance() {
    if (s_[i_] == '\n') {
      ++line_;
      column_ = 1;
    } else {
      ++column_;
    }
    ++i_;
  }
  void skipSpaceAndComments() {
    while (i_ < s_.size()) {
      if (std::isspace(static_cast<unsigned char>(s_[i_]))) {
        advance();
      } else if (s_.compare(i_, 2, "--") == 0) {
        while (i_ < s_.size() && s_[i_] != '\n') advance();
      } else {
        return;
      }
    }
  }
  // digits [. digits] [e [+-] digits], as HyperFun writes numbers (a leading '.' allowed)
  double number(std::string& text) {
    const std::size_t start = i_;
    auto digits = [&] {
      while (i_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[i_]))) advance();
    };
    digits();
    if (i_ < s_.size() && s_[i_] == '.') {
      advance();
      digits();
    }
    if (i_ < s_.size() && (s_[i_] == 'e' || s_[i_] == 'E')) {
      const Location at = here();
      advance();
      if (i_ < s_.size() && (s_[i_] == '+' || s_[i_] == '-')) advance();
      if (i_ >= s_.size() || !std::isdigit(static_cast<unsigned char>(s_[i_])))
        throw ModelError(located(source_, at, "a number's exponent has no digits"));
      digits();
    }
    text = s_.substr(start, i_ - start);
    const double v = std::strtod(text.c_str(), nullptr);
    if (!std::isfinite(v))
      throw ModelError(located(source_, here(), "the number " + text + " is too large"));
    return v;
  }

  const std::string& s_;
  const std::string& source_;
  std::size_t i_ = 0;
  int line_ = 1, column_ = 1;
};

class Parser {
 public:
  Parser(std::vector<Token> tokens, const std::string& source)
      : t_(std::move(tokens)), source_(source) {}

  Program program() {
    Program p;
    while (peek().kind != Token::Kind::End) p.bodies.push_back(body());
    if (p.bodies.empty())
      throw ModelError(located(source_, peek().at,
                               "no model: a HyperFun program is one or more bodies such as "
                               "my_model(x[3], a[1]) { my_model = ...; }"));
    return p;
  }

 private:
  struct Nesting {
    explicit Nesting(Parser& p) : p_(p) {
      if (++p_.depth_ > kMaxNesting)
        throw ModelError(p_.error(p_.peek().at,
                                  "nested deeper than " + std::to_string(kMaxNesting) + " levels"));
    }
    ~Nesting() { --p_.depth_; }
    Parser& p_;
  };

  std::string error(Location at, const std::string& what) const {
    return located(source_, at, what);
  }
  const Token& peek(std::size_t ahead = 0) const {
    return t_[std::min(pos_ + ahead, t_.size() - 1)];
  }
  bool isSymbol(const char* s, std::size_t ahead = 0) const {
    return peek(ahead).kind == Token::Kind::Symbol && peek(ahead).text == s;
  }
  bool isWord(const char* w, std::size_t ahead = 0) const {
    return peek(ahead).kind == Token::Kind::Name && peek(ahead).text == w;
  }
  bool acceptSymbol(const char* s) {
    if (!isSymbol(s)) return false;
    ++pos_;
    return true;
  }
  static std::string describe(const Token& t) {
    switch (t.kind) {
      case Token::Kind::End:
        return "the end of the file";
      case Token::Kind::Number:
        return "the number " + t.text;
      case Token::Kind::Name:
        return "'" + t.text + "'";
      case Token::Kind::Symbol:
        return "'" + t.text + "'";
    }
    return "?";
  }
  [[noreturn]] void expected(const std::string& what) const {
    throw ModelError(error(peek().at, "expected " + what + ", found " + describe(peek())));
  }
  void expectSymbol(const char* s) {
    if (!acceptSymbol(s)) expected(std::string("'") + s + "'");
  }
  void expectWord(const char* w) {
    if (!isWord(w)) expected(std::string("'") + w + "'");
    ++pos_;
  }
  Token name(const char* what) {
    if (peek().kind != Token::Kind::Name) expected(what);
    return t_[pos_++];
  }
  int size() {
    const Token& t = peek();
    if (t.kind != Token::Kind::Number) expected("an array size");
    ++pos_;
    const double rounded = std::floor(t.number + 0.5);
    if (rounded < 1 || rounded > 1e6)
      throw ModelError(error(t.at, "an array size of " + t.text + "; allowed: 1 to 1000000"));
    return static_cast<int>(rounded);
  }
  // [x|a|s] '[' size ']'
  int headerArray(const char* which) {
    expectWord(which);
    expectSymbol("[");
    const int n = size();
    expectSymbol("]");
    return n;
  }

  Body body() {
    Body b;
    const Token n = name("a body name such as my_model");
    b.name = n.text;
    b.at = n.at;
    expectSymbol("(");
    b.coordinates = headerArray("x");
    expectSymbol(",");
    b.parameters = headerArray("a");
    if (acceptSymbol(",")) headerArray("s");
    expectSymbol(")");
    expectSymbol("{");
    while (isWord("array")) {
      ++pos_;
      do {
        const Token a = name("an array name");
        expectSymbol("[");
        const int n = size();
        expectSymbol("]");
        b.arrays.push_back({a.text, n, a.at});
      } while (acceptSymbol(","));
      expectSymbol(";");
    }
    b.statements = statements(b.name);
    if (!isWord(b.name.c_str()))
      expected("a statement, or '" + b.name + " = ...;' giving the body's value");
    ++pos_;
    expectSymbol("=");
    b.result = expression();
    expectSymbol(";");
    expectSymbol("}");
    return b;
  }

  // Statements up to one that is not a statement (the body's own assignment, else, endif,
  // endloop, '}').
  std::vector<Statement> statements(const std::string& bodyName) {
    Nesting guard(*this);
    std::vector<Statement> out;
    for (;;) {
      const Token& t = peek();
      if (t.kind != Token::Kind::Name) return out;
      if (t.text == "if") {
        out.push_back(ifStatement(bodyName));
      } else if (t.text == "while") {
        out.push_back(whileStatement(bodyName));
      } else if (t.text == bodyName || t.text == "else" || t.text == "endif" ||
                 t.text == "endloop" || t.text == "then" || t.text == "loop") {
        return out;
      } else {
        out.push_back(assignment());
      }
    }
  }
  Statement ifStatement(const std::string& bodyName) {
    Statement s;
    s.kind = Statement::Kind::If;
    s.at = peek().at;
    ++pos_;
    s.value = condition();
    expectWord("then");
    s.body = statements(bodyName);
    if (isWord("else")) {
      ++pos_;
      s.otherwise = statements(bodyName);
    }
    expectWord("endif");
    expectSymbol(";");
    return s;
  }
  Statement whileStatement(const std::string& bodyName) {
    Statement s;
    s.kind = Statement::Kind::While;
    s.at = peek().at;
    ++pos_;
    s.value = condition();
    expectWord("loop");
    s.body = statements(bodyName);
    expectWord("endloop");
    expectSymbol(";");
    return s;
  }
  Statement assignment() {
    Statement s;
    const Token n = t_[pos_++];
    s.at = n.at;
    s.name = n.text;
    if (acceptSymbol("[")) {
      s.kind = Statement::Kind::AssignElement;
      s.index = expression();
      expectSymbol("]");
      expectSymbol("=");
      s.value = expression();
    } else {
      expectSymbol("=");
      if (acceptSymbol("[")) {
        s.kind = Statement::Kind::AssignArray;
        do {
          double sign = 1.0;
          if (acceptSymbol("-"))
            sign = -1.0;
          else
            acceptSymbol("+");
          if (peek().kind != Token::Kind::Number) expected("a number (an array is given numbers)");
          s.numbers.push_back(sign * t_[pos_++].number);
        } while (acceptSymbol(","));
        expectSymbol("]");
      } else {
        s.kind = Statement::Kind::Assign;
        s.value = expression();
      }
    }
    expectSymbol(";");
    return s;
  }

  static AstPtr node(Ast::Kind kind, Location at, std::string text) {
    auto a = std::make_unique<Ast>();
    a->kind = kind;
    a->at = at;
    a->text = std::move(text);
    return a;
  }
  static AstPtr binary(const Token& op, AstPtr left, AstPtr right) {
    AstPtr a = node(Ast::Kind::Binary, op.at, op.text);
    a->args.push_back(std::move(left));
    a->args.push_back(std::move(right));
    return a;
  }

  // HyperFun's precedence, as its interpreter parses it: + - | & \ @ on one level, then * /,
  // then ^ (from the left), then the signs + - ~ (so -x^2 is (-x)^2).
  AstPtr expression() {
    Nesting guard(*this);
    AstPtr left = product();
    for (;;) {
      bool found = false;
      for (const char* op : {"+", "-", "|", "&", "\\", "@"}) found = found || isSymbol(op);
      if (!found) return left;
      const Token op = t_[pos_++];
      left = binary(op, std::move(left), product());
    }
  }
  AstPtr product() {
    AstPtr left = power();
    while (isSymbol("*") || isSymbol("/")) {
      const Token op = t_[pos_++];
      left = binary(op, std::move(left), power());
    }
    return left;
  }
  AstPtr power() {
    AstPtr left = signedPrimary();
    while (isSymbol("^")) {
      const Token op = t_[pos_++];
      left = binary(op, std::move(left), signedPrimary());
    }
    return left;
  }
  AstPtr signedPrimary() {
    Nesting guard(*this);
    const Token t = peek();
    if (isSymbol("-") || isSymbol("+") || isSymbol("~")) {
      ++pos_;
      AstPtr a = node(Ast::Kind::Unary, t.at, t.text == "-" ? "neg" : t.text == "+" ? "pos" : "~");
      a->args.push_back(signedPrimary());
      return a;
    }
    return primary();
  }
  AstPtr primary() {
    const Token t = peek();
    if (t.kind == Token::Kind::Number) {
      ++pos_;
      AstPtr a = node(Ast::Kind::Number, t.at, t.text);
      a->number = t.number;
      return a;
    }
    if (acceptSymbol("(")) {
      AstPtr inner = expression();
      expectSymbol(")");
      return inner;
    }
    if (t.kind != Token::Kind::Name) expected("a value");
    ++pos_;
    if (acceptSymbol("[")) {
      AstPtr a = node(Ast::Kind::Element, t.at, t.text);
      a->args.push_back(expression());
      expectSymbol("]");
      return a;
    }
    if (acceptSymbol("(")) {
      AstPtr a = node(Ast::Kind::Call, t.at, t.text);
      if (!acceptSymbol(")")) {
        do a->args.push_back(expression());
        while (acceptSymbol(","));
        expectSymbol(")");
      }
      return a;
    }
    return node(Ast::Kind::Name, t.at, t.text);
  }

  // Conditions: comparisons joined by and/or (one level, from the left), 'not', parentheses.
  AstPtr condition() {
    Nesting guard(*this);
    AstPtr left = comparison();
    while (isWord("and") || isWord("or")) {
      const Token op = t_[pos_++];
      left = binary(op, std::move(left), comparison());
    }
    return left;
  }
  AstPtr comparison() {
    AstPtr left = conditionTerm();
    for (;;) {
      bool found = false;
      for (const char* op : {"<", "<=", ">", ">=", "=", "/="}) found = found || isSymbol(op);
      if (!found) return left;
      const Token op = t_[pos_++];
      left = binary(op, std::move(left), conditionTerm());
    }
  }
  AstPtr conditionTerm() {
    Nesting guard(*this);
    const Token t = peek();
    if (isWord("not")) {
      ++pos_;
      AstPtr a = node(Ast::Kind::Unary, t.at, "not");
      a->args.push_back(conditionTerm());
      return a;
    }
    if (acceptSymbol("(")) {
      AstPtr inner = condition();
      expectSymbol(")");
      return inner;
    }
    return expression();
  }

  std::vector<Token> t_;
  const std::string& source_;
  std::size_t pos_ = 0;
  int depth_ = 0;
};

}  // namespace

Program parseProgram(const std::string& text, const std::string& source) {
  return Parser(Lexer(text, source).tokens(), source).program();
}

}  // namespace frep::hyperfun
