#pragma once
// Internal: a field list named once and walked in either direction.
//
//   SRICS_FIELDS(op, a, b, version, run_id)
//     expands to  op(a.version, b.version, "version"); op(a.run_id, b.run_id, "run_id");
//
// With `op` copying from b to a or from a to b, one list serves both conversions, so adding a
// field to a type means adding one name in one place.

#define SRICS_FIELDS(op, a, b, ...) __VA_OPT__(SRICS_FIELDS_EXPAND(SRICS_FIELDS_ONE(op, a, b, __VA_ARGS__)))

// the standard recursive __VA_OPT__ idiom: 4^4 = 256 rescans, far more than any list here
#define SRICS_FIELDS_EXPAND(...) \
  SRICS_FIELDS_EXPAND3(SRICS_FIELDS_EXPAND3(SRICS_FIELDS_EXPAND3(SRICS_FIELDS_EXPAND3(__VA_ARGS__))))
#define SRICS_FIELDS_EXPAND3(...) \
  SRICS_FIELDS_EXPAND2(SRICS_FIELDS_EXPAND2(SRICS_FIELDS_EXPAND2(SRICS_FIELDS_EXPAND2(__VA_ARGS__))))
#define SRICS_FIELDS_EXPAND2(...) \
  SRICS_FIELDS_EXPAND1(SRICS_FIELDS_EXPAND1(SRICS_FIELDS_EXPAND1(SRICS_FIELDS_EXPAND1(__VA_ARGS__))))
#define SRICS_FIELDS_EXPAND1(...) __VA_ARGS__
#define SRICS_FIELDS_ONE(op, a, b, field, ...) \
  op(a.field, b.field, #field);                \
  __VA_OPT__(SRICS_FIELDS_AGAIN SRICS_FIELDS_PARENS(op, a, b, __VA_ARGS__))
#define SRICS_FIELDS_PARENS ()
#define SRICS_FIELDS_AGAIN() SRICS_FIELDS_ONE
