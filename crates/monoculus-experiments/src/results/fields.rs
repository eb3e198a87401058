//! [`fields_of`]: the fields of one record, each as the CSV writer writes it (before
//! quoting), taken straight from the record's `Serialize` with no CSV text between.

use serde::Serialize;
use serde::ser::{self, Impossible};

/// The fields of a serialised record, in column order: what the CSV writer writes for
/// each (integers and floats in the writer's own forms, `true`/`false`, an absent
/// option as an empty field), unquoted, as a CSV reader gives them back (tested against
/// one). A record is a struct or a tuple of scalars, or one scalar.
pub(crate) fn fields_of<T: Serialize>(value: &T) -> Vec<String> {
    let mut out = Vec::with_capacity(48);
    let fields = Fields {
        out: &mut out,
        nested: false,
    };
    value
        .serialize(fields)
        .expect("a row is a struct or a tuple of scalars");
    out
}

/// Why a value is not a record of scalars.
#[derive(Debug)]
struct NotScalar(String);

impl std::fmt::Display for NotScalar {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for NotScalar {}

impl ser::Error for NotScalar {
    fn custom<T: std::fmt::Display>(msg: T) -> Self {
        NotScalar(msg.to_string())
    }
}

/// Where the fields go, one by one: a scalar is one field, a struct or a tuple (at the
/// top only) one field a member.
struct Fields<'a> {
    out: &'a mut Vec<String>,
    /// Inside the record: a struct or a tuple here is not a field.
    nested: bool,
}

impl Fields<'_> {
    fn push(self, field: String) -> Result<(), NotScalar> {
        self.out.push(field);
        Ok(())
    }

    /// The record itself, whose members are fields.
    fn record(self, what: &str) -> Result<Self, NotScalar> {
        if self.nested {
            return not_scalar(what);
        }
        Ok(Fields {
            out: self.out,
            nested: true,
        })
    }

    fn member<T: ?Sized + Serialize>(&mut self, value: &T) -> Result<(), NotScalar> {
        value.serialize(Fields {
            out: self.out,
            nested: true,
        })
    }
}

fn not_scalar<T>(what: &str) -> Result<T, NotScalar> {
    Err(NotScalar(format!("a field cannot be {what}")))
}

macro_rules! scalars {
    ($($method:ident: $ty:ty => $text:expr;)*) => {
        $(
            fn $method(self, v: $ty) -> Result<(), NotScalar> {
                #[allow(clippy::redundant_closure_call, reason = "one pattern for every scalar")]
                self.push(($text)(v))
            }
        )*
    };
}

impl ser::Serializer for Fields<'_> {
    type Ok = ();
    type Error = NotScalar;
    type SerializeSeq = Impossible<(), NotScalar>;
    type SerializeTuple = Self;
    type SerializeTupleStruct = Impossible<(), NotScalar>;
    type SerializeTupleVariant = Impossible<(), NotScalar>;
    type SerializeMap = Impossible<(), NotScalar>;
    type SerializeStruct = Self;
    type SerializeStructVariant = Impossible<(), NotScalar>;

    scalars! {
        serialize_bool: bool => |v: bool| if v { "true" } else { "false" }.to_string();
        serialize_i8: i8 => |v: i8| v.to_string();
        serialize_i16: i16 => |v: i16| v.to_string();
        serialize_i32: i32 => |v: i32| v.to_string();
        serialize_i64: i64 => |v: i64| v.to_string();
        serialize_u8: u8 => |v: u8| v.to_string();
        serialize_u16: u16 => |v: u16| v.to_string();
        serialize_u32: u32 => |v: u32| v.to_string();
        serialize_u64: u64 => |v: u64| v.to_string();
        serialize_f32: f32 => |v: f32| ryu::Buffer::new().format(v).to_string();
        serialize_f64: f64 => |v: f64| ryu::Buffer::new().format(v).to_string();
        serialize_char: char => |v: char| v.to_string();
        serialize_str: &str => |v: &str| v.to_string();
        serialize_bytes: &[u8] => |v: &[u8]| String::from_utf8_lossy(v).into_owned();
    }

    fn serialize_none(self) -> Result<(), NotScalar> {
        self.push(String::new())
    }

    fn serialize_some<T: ?Sized + Serialize>(self, value: &T) -> Result<(), NotScalar> {
        value.serialize(self)
    }

    fn serialize_unit(self) -> Result<(), NotScalar> {
        self.push(String::new())
    }

    fn serialize_unit_struct(self, name: &'static str) -> Result<(), NotScalar> {
        self.push(name.to_string())
    }

    fn serialize_unit_variant(
        self,
        _name: &'static str,
        _index: u32,
        variant: &'static str,
    ) -> Result<(), NotScalar> {
        self.push(variant.to_string())
    }

    fn serialize_newtype_struct<T: ?Sized + Serialize>(
        self,
        _name: &'static str,
        value: &T,
    ) -> Result<(), NotScalar> {
        value.serialize(self)
    }

    fn serialize_newtype_variant<T: ?Sized + Serialize>(
        self,
        _name: &'static str,
        _index: u32,
        _variant: &'static str,
        _value: &T,
    ) -> Result<(), NotScalar> {
        not_scalar("an enum with data")
    }

    fn serialize_seq(self, _len: Option<usize>) -> Result<Self::SerializeSeq, NotScalar> {
        not_scalar("a sequence")
    }

    fn serialize_tuple(self, _len: usize) -> Result<Self, NotScalar> {
        self.record("a tuple")
    }

    fn serialize_tuple_struct(
        self,
        _name: &'static str,
        _len: usize,
    ) -> Result<Self::SerializeTupleStruct, NotScalar> {
        not_scalar("a tuple struct")
    }

    fn serialize_tuple_variant(
        self,
        _name: &'static str,
        _index: u32,
        _variant: &'static str,
        _len: usize,
    ) -> Result<Self::SerializeTupleVariant, NotScalar> {
        not_scalar("an enum with data")
    }

    fn serialize_map(self, _len: Option<usize>) -> Result<Self::SerializeMap, NotScalar> {
        not_scalar("a map")
    }

    fn serialize_struct(self, _name: &'static str, _len: usize) -> Result<Self, NotScalar> {
        self.record("a struct")
    }

    fn serialize_struct_variant(
        self,
        _name: &'static str,
        _index: u32,
        _variant: &'static str,
        _len: usize,
    ) -> Result<Self::SerializeStructVariant, NotScalar> {
        not_scalar("an enum with data")
    }
}

impl ser::SerializeStruct for Fields<'_> {
    type Ok = ();
    type Error = NotScalar;

    fn serialize_field<T: ?Sized + Serialize>(
        &mut self,
        _key: &'static str,
        value: &T,
    ) -> Result<(), NotScalar> {
        self.member(value)
    }

    fn end(self) -> Result<(), NotScalar> {
        Ok(())
    }
}

impl ser::SerializeTuple for Fields<'_> {
    type Ok = ();
    type Error = NotScalar;

    fn serialize_element<T: ?Sized + Serialize>(&mut self, value: &T) -> Result<(), NotScalar> {
        self.member(value)
    }

    fn end(self) -> Result<(), NotScalar> {
        Ok(())
    }
}
