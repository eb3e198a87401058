//! [`record_of`]: the fields of one record, each as the CSV writer writes it (before
//! quoting), taken straight from the record's `Serialize` with no CSV text between.

use serde::Serialize;
use serde::ser::{self, Impossible};

/// The fields of a serialised record, in column order: what the CSV writer writes for
/// each (integers and floats in the writer's own forms, `true`/`false`, an absent
/// option as an empty field), unquoted, as a CSV reader gives them back (tested against
/// one). A record is a struct or a tuple of scalars, or one scalar.
pub(crate) fn fields_of<T: Serialize>(value: &T) -> Vec<String> {
    record_of(value).iter().map(String::from).collect()
}

/// [`fields_of`] as one record (its fields in one buffer), appended to `out`.
pub(crate) fn push_fields<T: Serialize>(value: &T, out: &mut csv::StringRecord) {
    let fields = Fields { out, nested: false };
    value
        .serialize(fields)
        .expect("a row is a struct or a tuple of scalars");
}

/// [`fields_of`] as one record.
pub(crate) fn record_of<T: Serialize>(value: &T) -> csv::StringRecord {
    let mut out = csv::StringRecord::with_capacity(512, 48);
    push_fields(value, &mut out);
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
    out: &'a mut csv::StringRecord,
    /// Inside the record: a struct or a tuple here is not a field.
    nested: bool,
}

impl Fields<'_> {
    fn push(self, field: &str) -> Result<(), NotScalar> {
        self.out.push_field(field);
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

/// Integers and floats, each formatted into its own stack buffer (the `csv` writer's
/// forms: itoa's and ryu's).
macro_rules! numbers {
    ($($method:ident: $ty:ty => $buffer:ty;)*) => {
        $(
            fn $method(self, v: $ty) -> Result<(), NotScalar> {
                self.push(<$buffer>::new().format(v))
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

    numbers! {
        serialize_i8: i8 => itoa::Buffer;
        serialize_i16: i16 => itoa::Buffer;
        serialize_i32: i32 => itoa::Buffer;
        serialize_i64: i64 => itoa::Buffer;
        serialize_u8: u8 => itoa::Buffer;
        serialize_u16: u16 => itoa::Buffer;
        serialize_u32: u32 => itoa::Buffer;
        serialize_u64: u64 => itoa::Buffer;
        serialize_f32: f32 => ryu::Buffer;
        serialize_f64: f64 => ryu::Buffer;
    }

    fn serialize_bool(self, v: bool) -> Result<(), NotScalar> {
        self.push(if v { "true" } else { "false" })
    }

    fn serialize_char(self, v: char) -> Result<(), NotScalar> {
        self.push(v.encode_utf8(&mut [0; 4]))
    }

    fn serialize_str(self, v: &str) -> Result<(), NotScalar> {
        self.push(v)
    }

    fn serialize_bytes(self, v: &[u8]) -> Result<(), NotScalar> {
        self.push(&String::from_utf8_lossy(v))
    }

    fn serialize_none(self) -> Result<(), NotScalar> {
        self.push("")
    }

    fn serialize_some<T: ?Sized + Serialize>(self, value: &T) -> Result<(), NotScalar> {
        value.serialize(self)
    }

    fn serialize_unit(self) -> Result<(), NotScalar> {
        self.push("")
    }

    fn serialize_unit_struct(self, name: &'static str) -> Result<(), NotScalar> {
        self.push(name)
    }

    fn serialize_unit_variant(
        self,
        _name: &'static str,
        _index: u32,
        variant: &'static str,
    ) -> Result<(), NotScalar> {
        self.push(variant)
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
