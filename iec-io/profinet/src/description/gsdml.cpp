// GSDML (PROFINET device description, GSDML V2.x schema) with libxml2: the
// document is read without network access and without entity expansion;
// elements are matched by local name, so the default GSDML namespace (or
// none) both work.
#include "plc/profinet/description/gsdml.hpp"

#include <libxml/parser.h>
#include <libxml/tree.h>

#include <algorithm>
#include <boost/algorithm/string/trim.hpp>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <sstream>

#include "plc/iec_literal.hpp"

namespace plc::profinet {

namespace {

using Node = xmlNode*;

struct DocFree {
  void operator()(xmlDoc* d) const { xmlFreeDoc(d); }
};
struct CtxtFree {
  void operator()(xmlParserCtxt* c) const { xmlFreeParserCtxt(c); }
};

class Reader {
 public:
  explicit Reader(std::string path) : path_(std::move(path)) {}

  [[noreturn]] void fail(Node n, const std::string& what) const {
    throw GsdmlError(path_ + ":" + std::to_string(n ? xmlGetLineNo(n) : 0) + ": " + what);
  }

  static bool is(Node n, const char* name) {
    return n && n->type == XML_ELEMENT_NODE && xmlStrcmp(n->name, BAD_CAST name) == 0;
  }
  static Node child(Node n, const char* name) {
    for (Node c = n ? n->children : nullptr; c; c = c->next)
      if (is(c, name)) return c;
    return nullptr;
  }
  static std::vector<Node> children(Node n, const char* name) {
    std::vector<Node> out;
    for (Node c = n ? n->children : nullptr; c; c = c->next)
      if (is(c, name)) out.push_back(c);
    return out;
  }
  Node need(Node n, const char* name) const {
    Node c = child(n, name);
    if (!c)
      fail(n,
           std::string("<") + reinterpret_cast<const char*>(n->name) + "> has no <" + name + ">");
    return c;
  }
  static std::optional<std::string> attr(Node n, const char* name) {
    xmlChar* v = xmlGetProp(n, BAD_CAST name);
    if (!v) return std::nullopt;
    std::string s(reinterpret_cast<const char*>(v));
    xmlFree(v);
    return s;
  }
  std::string need_attr(Node n, const char* name) const {
    auto v = attr(n, name);
    if (!v)
      fail(n, std::string("<") + reinterpret_cast<const char*>(n->name) + "> has no " + name +
                  " attribute");
    return *v;
  }
  // GSDML numbers: decimal, or 0x-prefixed hex.
  std::uint64_t number(Node n, const std::string& text, std::uint64_t max, const char* what) const {
    std::string t = text;
    if (t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X')) t = "16#" + t.substr(2);
    const auto v = parse_iec_unsigned(t);
    if (!v || *v > max || t.find('#') != t.rfind('#'))
      fail(n, std::string(what) + " '" + text + "' is not a number 0.." + std::to_string(max));
    return *v;
  }
  std::uint64_t number_attr(Node n, const char* name, std::uint64_t max) const {
    return number(n, need_attr(n, name), max, name);
  }

  void load() {
    // Checked first so that a missing file is our one-line error, not
    // libxml2's I/O warning on stderr as well.
    if (std::FILE* f = std::fopen(path_.c_str(), "rb")) {
      std::fclose(f);
    } else {
      throw GsdmlError(path_ + ":0: cannot read the file: " + std::strerror(errno));
    }
    std::unique_ptr<xmlParserCtxt, CtxtFree> ctxt(xmlNewParserCtxt());
    if (!ctxt) throw GsdmlError(path_ + ":0: out of memory");
    doc_.reset(xmlCtxtReadFile(ctxt.get(), path_.c_str(), nullptr,
                               XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING));
    if (!doc_) {
      const xmlError* e = xmlCtxtGetLastError(ctxt.get());
      std::string msg = e && e->message ? e->message : "cannot read the file";
      while (!msg.empty() && (msg.back() == '\n' || msg.back() == ' ')) msg.pop_back();
      throw GsdmlError(path_ + ":" + std::to_string(e ? e->line : 0) + ": " + msg);
    }
    root_ = xmlDocGetRootElement(doc_.get());
    if (!is(root_, "ISO15745Profile"))
      fail(root_, "not a GSDML file (the root element is not <ISO15745Profile>)");
    body_ = need(root_, "ProfileBody");
    app_ = need(body_, "ApplicationProcess");
    // Names: ExternalTextList/PrimaryLanguage/Text TextId -> Value.
    if (Node texts = child(child(app_, "ExternalTextList"), "PrimaryLanguage"))
      for (Node t : children(texts, "Text"))
        if (auto id = attr(t, "TextId"))
          if (auto v = attr(t, "Value")) text_[*id] = *v;
  }

  // The name of a DAP/module: ModuleInfo/Name TextId, looked up.
  std::string name_of(Node item) const {
    Node name = child(child(item, "ModuleInfo"), "Name");
    if (!name) return "";
    auto id = attr(name, "TextId");
    if (!id) return "";
    auto it = text_.find(*id);
    return it == text_.end() ? "" : it->second;
  }

  Node find_item(Node list, const char* item, const std::string& id_or_name,
                 const char* what) const {
    std::vector<Node> items = children(list, item);
    for (Node n : items)
      if (attr(n, "ID") == id_or_name) return n;
    for (Node n : items)
      if (!id_or_name.empty() && name_of(n) == id_or_name) return n;
    std::string known;
    for (Node n : items) known += (known.empty() ? "" : ", ") + attr(n, "ID").value_or("?");
    fail(list, std::string("no ") + what + " '" + id_or_name +
                   "' (ID or name; the file has: " + known + ")");
  }

  std::uint16_t data_length(Node io_dir) const {
    std::uint64_t total = 0;
    for (Node item : children(io_dir, "DataItem")) {
      const std::string type = need_attr(item, "DataType");
      std::uint64_t n = 0;
      static const std::map<std::string, unsigned> sizes = {
          {"Integer8", 1},
          {"Unsigned8", 1},
          {"Integer16", 2},
          {"Unsigned16", 2},
          {"Integer32", 4},
          {"Unsigned32", 4},
          {"Integer64", 8},
          {"Unsigned64", 8},
          {"Float32", 4},
          {"Float64", 8},
          {"Boolean", 1},
          {"Date", 7},
          {"TimeOfDay with date indication", 6},
          {"TimeOfDay without date indication", 4},
          {"TimeDifference with date indication", 6},
          {"TimeDifference without date indication", 4},
          {"NetworkTime", 8},
          {"NetworkTimeDifference", 8},
          {"F_MessageTrailer4Byte", 4},
          {"F_MessageTrailer5Byte", 5},
          {"Unsigned8+Unsigned8", 2},
          {"Float32+Unsigned8", 5},
          {"Unsigned16_S", 2},
          {"Integer16_S", 2},
          {"Unsigned8_S", 1}};
      if (type == "OctetString" || type == "VisibleString" || type == "UnicodeString8" ||
          type == "OctetString_S") {
        n = number_attr(item, "Length", 1440);
      } else if (auto it = sizes.find(type); it != sizes.end()) {
        n = it->second;
      } else {
        fail(item, "DataItem of unknown DataType '" + type + "'");
      }
      total += n;
    }
    if (total > 1439) fail(io_dir, "IO data longer than one RT_CLASS_1 frame (1440 bytes)");
    return static_cast<std::uint16_t>(total);
  }

  // A ParameterRecordDataItem with its defaults: Const blocks, then Ref
  // values at their ByteOffset (big-endian) / BitOffset.
  StartupRecord record(Node item) const {
    StartupRecord r;
    r.index = static_cast<std::uint16_t>(number_attr(item, "Index", 0xFFFF));
    const auto len = number_attr(item, "Length", 4096);
    r.data.assign(len, 0);
    for (Node c : children(item, "Const")) {
      std::size_t off = attr(c, "ByteOffset") ? number_attr(c, "ByteOffset", len) : 0;
      std::istringstream in(need_attr(c, "Data"));
      std::string byte;
      while (std::getline(in, byte, ',')) {
        byte.erase(std::remove(byte.begin(), byte.end(), ' '), byte.end());
        if (off >= len) fail(c, "Const data run past the record's Length");
        r.data[off++] = static_cast<std::uint8_t>(number(c, byte, 255, "Const byte"));
      }
    }
    for (Node ref : children(item, "Ref")) {
      const std::string type = need_attr(ref, "DataType");
      const std::size_t off = number_attr(ref, "ByteOffset", len);
      const auto def_text = attr(ref, "DefaultValue").value_or("0");
      std::int64_t value = 0;
      {
        std::string t = def_text;
        bool neg = !t.empty() && t[0] == '-';
        if (neg) t = t.substr(1);
        value = static_cast<std::int64_t>(number(ref, t, 0xFFFFFFFF, "DefaultValue"));
        if (neg) value = -value;
      }
      unsigned bytes = 0;
      if (type == "Unsigned8" || type == "Integer8")
        bytes = 1;
      else if (type == "Unsigned16" || type == "Integer16")
        bytes = 2;
      else if (type == "Unsigned32" || type == "Integer32")
        bytes = 4;
      if (bytes) {
        if (off + bytes > len) fail(ref, "Ref runs past the record's Length");
        for (unsigned i = 0; i < bytes; ++i)
          r.data[off + i] =
              static_cast<std::uint8_t>(static_cast<std::uint64_t>(value) >> (8 * (bytes - 1 - i)));
      } else if (type == "Bit" || type == "BitArea") {
        const auto bit = attr(ref, "BitOffset") ? number_attr(ref, "BitOffset", 7) : 0;
        const auto width =
            type == "Bit" ? 1 : (attr(ref, "BitLength") ? number_attr(ref, "BitLength", 8) : 1);
        if (off >= len || bit + width > 8) fail(ref, "Ref bits run past their byte or the record");
        const unsigned mask = ((1u << width) - 1u) << bit;
        r.data[off] = static_cast<std::uint8_t>((r.data[off] & ~mask) |
                                                ((static_cast<unsigned>(value) << bit) & mask));
      } else {
        fail(ref, "Ref of DataType '" + type +
                      "' is not supported for start-up records "
                      "(Unsigned/Integer 8/16/32, Bit, BitArea)");
      }
    }
    return r;
  }

  // Every VirtualSubmoduleItem of a DAP or module; subslots from
  // FixedInSubslots, else numbered 1, 2, ...
  std::vector<SubmoduleDescription> submodules(Node item) const {
    std::vector<SubmoduleDescription> out;
    std::uint16_t next = 1;
    for (Node v : children(child(item, "VirtualSubmoduleList"), "VirtualSubmoduleItem")) {
      SubmoduleDescription s;
      s.submodule_ident =
          static_cast<std::uint32_t>(number_attr(v, "SubmoduleIdentNumber", 0xFFFFFFFF));
      s.api = attr(v, "API") ? static_cast<std::uint32_t>(number_attr(v, "API", 0xFFFFFFFF)) : 0;
      if (auto fixed = attr(v, "FixedInSubslots")) {
        // "1" or "1..2": the first.
        s.subslot = static_cast<std::uint16_t>(
            number(v, fixed->substr(0, fixed->find_first_of(". ")), 0xFFFF, "FixedInSubslots"));
      } else {
        s.subslot = next;
      }
      next = static_cast<std::uint16_t>(s.subslot + 1);
      if (Node io = child(v, "IOData")) {
        if (Node in = child(io, "Input")) s.input_length = data_length(in);
        if (Node o = child(io, "Output")) s.output_length = data_length(o);
      }
      for (Node r : children(child(v, "RecordDataList"), "ParameterRecordDataItem"))
        s.records.push_back(record(r));
      out.push_back(std::move(s));
    }
    std::sort(out.begin(), out.end(),
              [](const auto& a, const auto& b) { return a.subslot < b.subslot; });
    return out;
  }

  // "1..3 5" style slot lists.
  bool slot_in(Node n, const std::string& list, std::uint16_t slot) const {
    std::istringstream in(list);
    std::string part;
    while (in >> part) {
      const auto dots = part.find("..");
      const auto lo = number(n, part.substr(0, dots), 0x7FFF, "slot");
      const auto hi =
          dots == std::string::npos ? lo : number(n, part.substr(dots + 2), 0x7FFF, "slot");
      if (slot >= lo && slot <= hi) return true;
    }
    return false;
  }

  DeviceDescription describe(const GsdmlSelection& sel) {
    DeviceDescription d;
    Node identity = need(body_, "DeviceIdentity");
    d.vendor_id = static_cast<std::uint16_t>(number_attr(identity, "VendorID", 0xFFFF));
    d.device_id = static_cast<std::uint16_t>(number_attr(identity, "DeviceID", 0xFFFF));
    Node daps = need(app_, "DeviceAccessPointList");
    Node dap = sel.dap.empty()
                   ? need(daps, "DeviceAccessPointItem")
                   : find_item(daps, "DeviceAccessPointItem", sel.dap, "DeviceAccessPointItem");
    ModuleDescription m0;
    m0.slot = 0;
    m0.module_ident = static_cast<std::uint32_t>(number_attr(dap, "ModuleIdentNumber", 0xFFFFFFFF));
    if (auto mdi = attr(dap, "MinDeviceInterval"))
      d.min_device_interval =
          std::chrono::nanoseconds(31250 * number(dap, *mdi, 4096, "MinDeviceInterval"));
    m0.submodules = submodules(dap);
    Node sys = child(dap, "SystemDefinedSubmoduleList");
    for (const char* kind : {"InterfaceSubmoduleItem", "PortSubmoduleItem"})
      for (Node s : children(sys, kind)) {
        SubmoduleDescription sd;
        sd.subslot = static_cast<std::uint16_t>(number_attr(s, "SubslotNumber", 0xFFFF));
        sd.submodule_ident =
            static_cast<std::uint32_t>(number_attr(s, "SubmoduleIdentNumber", 0xFFFFFFFF));
        m0.submodules.push_back(sd);
      }
    std::sort(m0.submodules.begin(), m0.submodules.end(),
              [](const auto& a, const auto& b) { return a.subslot < b.subslot; });
    d.modules.push_back(std::move(m0));

    Node modules = child(app_, "ModuleList");
    Node useable = child(dap, "UseableModules");
    auto picked = sel.modules;
    std::sort(picked.begin(), picked.end(),
              [](const auto& a, const auto& b) { return a.slot < b.slot; });
    for (std::size_t i = 0; i < picked.size(); ++i) {
      const auto& p = picked[i];
      if (p.slot == 0) throw GsdmlError(path_ + ":0: slot 0 is the DAP (choose it with gsdml_dap)");
      if (i > 0 && picked[i - 1].slot == p.slot)
        throw GsdmlError(path_ + ":0: slot " + std::to_string(p.slot) + " is chosen twice");
      if (!modules) fail(app_, "the file has no <ModuleList>");
      Node mod = find_item(modules, "ModuleItem", p.module, "ModuleItem");
      // The DAP says which modules go into which slots.
      if (useable) {
        const std::string id = need_attr(mod, "ID");
        Node ref = nullptr;
        for (Node r : children(useable, "ModuleItemRef"))
          if (attr(r, "ModuleItemTarget") == id) ref = r;
        if (!ref) fail(useable, "the DAP does not allow module '" + id + "'");
        const auto slots =
            attr(ref, "AllowedInSlots").value_or(attr(ref, "FixedInSlots").value_or(""));
        if (!slots.empty() && !slot_in(ref, slots, p.slot))
          fail(ref, "module '" + id + "' is allowed in slots " + slots + ", not in slot " +
                        std::to_string(p.slot));
      }
      ModuleDescription m;
      m.slot = p.slot;
      m.module_ident =
          static_cast<std::uint32_t>(number_attr(mod, "ModuleIdentNumber", 0xFFFFFFFF));
      m.submodules = submodules(mod);
      if (m.submodules.empty()) fail(mod, "the module has no VirtualSubmoduleItem");
      d.modules.push_back(std::move(m));
    }
    return d;
  }

 private:
  std::string path_;
  std::unique_ptr<xmlDoc, DocFree> doc_;
  Node root_ = nullptr, body_ = nullptr, app_ = nullptr;
  std::map<std::string, std::string> text_;
};

}  // namespace

DeviceDescription load_gsdml(const std::string& path, const GsdmlSelection& selection) {
  Reader r(path);
  r.load();
  return r.describe(selection);
}

std::vector<GsdmlSelection::Slot> parse_gsdml_modules(const std::string& text) {
  std::vector<GsdmlSelection::Slot> out;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ';')) {
    boost::algorithm::trim(item);
    if (item.empty()) continue;
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == item.size())
      throw std::invalid_argument("'" + item + "': expected SLOT=MODULE (ID or name)");
    const auto slot = parse_iec_unsigned(boost::algorithm::trim_copy(item.substr(0, eq)));
    if (!slot || *slot < 1 || *slot > 0x7FFF)
      throw std::invalid_argument("'" + item + "': the slot must be a number 1..32767");
    const std::string mod = boost::algorithm::trim_copy(item.substr(eq + 1));
    out.push_back({static_cast<std::uint16_t>(*slot), mod});
  }
  return out;
}

}  // namespace plc::profinet
